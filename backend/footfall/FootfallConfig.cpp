#include "footfall/FootfallConfig.h"

#include <stdexcept>

#include "io/Json.h"

namespace ambler::footfall {

namespace {

// Overwrites `value` when the object has the key.
void take(const io::JsonFields& f, const char* key, double& value) {
  if (f.has(key)) value = f.number(key);
}

}  // namespace

CostMapOptions readFootfallConfig(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  const io::JsonFields root(json, "footfall configuration '" + path.string() + "'");
  CostMapOptions o;
  if (root.has("foot")) {
    const auto f = root.object("foot");
    take(f, "diameter_m", o.foot.diameter_m);
    take(f, "min_support_fraction", o.foot.min_support_fraction);
    take(f, "max_tilt_deg", o.foot.max_tilt_deg);
    take(f, "sigma_margin", o.foot.sigma_margin);
    take(f, "equilibrium_moment_weight", o.foot.equilibrium_moment_weight);
    take(f, "support_bin_m", o.foot.support_bin_m);
  }
  if (root.has("limits")) {
    const auto f = root.object("limits");
    take(f, "reach_min_m", o.limits.reach_min_m);
    take(f, "reach_max_m", o.limits.reach_max_m);
    take(f, "elevation_min_m", o.limits.elevation_min_m);
    take(f, "elevation_max_m", o.limits.elevation_max_m);
  }
  if (root.has("weights")) {
    const auto f = root.object("weights");
    take(f, "roughness", o.weights.roughness);
    take(f, "slope", o.weights.slope);
    take(f, "body_advance", o.weights.body_advance);
    take(f, "visibility", o.weights.visibility);
  }
  if (root.has("roughness")) {
    const auto f = root.object("roughness");
    if (f.has("criterion")) {
      const auto name = f.string("criterion");
      const auto criterion = criterionFromName(name);
      if (!criterion)
        f.fail("criterion", "'" + name +
                                "' is not maxmin, planar, support, freevolume or "
                                "equilibrium");
      o.roughness_criterion = *criterion;
    }
    take(f, "scale", o.roughness_scale);
  }
  take(root, "max_body_advance_m", o.max_body_advance_m);
  try {
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw io::FormatError("footfall configuration '" + path.string() + "': " + e.what());
  }
  return o;
}

}  // namespace ambler::footfall
