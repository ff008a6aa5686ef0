#include "footfall/FootfallConfig.h"

#include <stdexcept>

#include "io/Json.h"

namespace ambler::footfall {

CostMapOptions readFootfallConfig(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  const io::JsonFields root(json, "footfall configuration '" + path.string() + "'");
  CostMapOptions o;
  // Numbers by section and key; a missing key keeps its default.
  const struct {
    const char* section;
    const char* key;
    double* value;
  } numbers[] = {
      {"foot", "diameter_m", &o.foot.diameter_m},
      {"foot", "min_support_fraction", &o.foot.min_support_fraction},
      {"foot", "max_tilt_deg", &o.foot.max_tilt_deg},
      {"foot", "sigma_margin", &o.foot.sigma_margin},
      {"foot", "equilibrium_moment_weight", &o.foot.equilibrium_moment_weight},
      {"foot", "support_bin_m", &o.foot.support_bin_m},
      {"foot", "clearance_m", &o.foot.clearance_m},
      {"limits", "reach_min_m", &o.limits.reach_min_m},
      {"limits", "reach_max_m", &o.limits.reach_max_m},
      {"limits", "elevation_min_m", &o.limits.elevation_min_m},
      {"limits", "elevation_max_m", &o.limits.elevation_max_m},
      {"weights", "roughness", &o.weights.roughness},
      {"weights", "slope", &o.weights.slope},
      {"weights", "body_advance", &o.weights.body_advance},
      {"weights", "visibility", &o.weights.visibility},
      {"roughness", "scale", &o.roughness_scale},
  };
  for (const auto& n : numbers) {
    if (!root.has(n.section)) continue;
    const auto f = root.object(n.section);
    if (f.has(n.key)) *n.value = f.number(n.key);
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
  }
  if (root.has("max_body_advance_m")) o.max_body_advance_m = root.number("max_body_advance_m");
  try {
    validate(o);
  } catch (const std::invalid_argument& e) {
    throw io::FormatError("footfall configuration '" + path.string() + "': " + e.what());
  }
  return o;
}

}  // namespace ambler::footfall
