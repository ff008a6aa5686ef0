#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/GridSpec.h"
#include "terrain/ElevationMap.h"

namespace ambler::footfall {

// The five footfall criteria of krotkov1989 §4, in its order of
// sophistication. Every score is lower-is-better.
enum class Criterion { kMaxMin, kPlanarFit, kSupportArea, kFreeVolume, kEquilibrium };
inline constexpr std::array<Criterion, 5> kAllCriteria{
    Criterion::kMaxMin, Criterion::kPlanarFit, Criterion::kSupportArea, Criterion::kFreeVolume,
    Criterion::kEquilibrium};

// "maxmin", "planar", "support", "freevolume", "equilibrium".
std::string_view criterionName(Criterion criterion);
std::optional<Criterion> criterionFromName(std::string_view name);
// Unit of the criterion's score: "m" or "m^3".
std::string_view criterionUnit(Criterion criterion);

// The foot and how the criteria judge it (docs/footfall.md).
struct FootOptions {
  double diameter_m = 0.30;            // Ambler's flat disk foot (krotkov1989 §4)
  double min_support_fraction = 0.25;  // A_min as a fraction of the foot's cells
  double max_tilt_deg = 15.0;          // planar fit: largest angle of the normal to the leg
  // Uncertainty margin: the criteria see the map raised by this many sigma
  // where the foot may touch and lowered by it below the foot.
  double sigma_margin = 2.0;
  // Equilibrium = V + weight * E / foot radius: at 1, all the free volume on
  // the rim of one side doubles the score.
  double equilibrium_moment_weight = 1.0;
  double support_bin_m = 5e-4;  // height resolution of the support-area order statistic
  // The sole stays this many whole map cells from any cell not known, the
  // most that fit in this distance (docs/footfall.md, "Clearance"); none
  // on maps with larger cells.
  double clearance_m = 0.05;
};

// Throws std::invalid_argument naming the first field out of range.
void validate(const FootOptions& options);

// A criterion's (or a cost's) value for a foot centred on each candidate
// cell; NaN where the foot cannot stand (a cell under it is unknown, in
// shadow or off the map, or a limit is exceeded).
struct ScoreMap {
  GridSpec grid;
  terrain::Layer score;
  std::string name;
  std::string unit;
  int validCount() const;
  // All NaN: nowhere to stand yet.
  static ScoreMap empty(const GridSpec& grid, std::string name, std::string unit);
};

struct Foothold {
  bool found = false;
  double x = 0.0, y = 0.0;  // foot centre [m]
  double score = 0.0;
  int row = 0, col = 0;  // in the score map's grid
};

// The lowest finite score; ties go to the candidate nearest the region's
// centre (where the operator or the gait planner aimed).
Foothold bestFoothold(const ScoreMap& map);

// Scores of one criterion over the cells of `map` whose centres lie in
// `region`. Throws std::invalid_argument for a region off the map or bad
// options.
ScoreMap evaluateFootfalls(const terrain::ElevationMap& map, const Box2& region,
                           Criterion criterion, const FootOptions& options = {});

// All five, in kAllCriteria order, from one pass over the region.
std::vector<ScoreMap> evaluateAllCriteria(const terrain::ElevationMap& map, const Box2& region,
                                          const FootOptions& options = {});

// The angle of the best-fit plane under each candidate to the horizontal
// [deg], NaN where the foot cannot stand.
ScoreMap planeTilt(const terrain::ElevationMap& map, const Box2& region,
                   const FootOptions& options = {});

// The same from statistics computed once (footfall/Footprint.h), for
// callers that need several maps of one region; the support area's order
// statistic only `with_support`.
struct FootprintStatistics;
FootprintStatistics footprintStatistics(const terrain::ElevationMap& map, const Box2& region,
                                        const FootOptions& options, bool with_support);
ScoreMap scoreMapOf(const FootprintStatistics& stats, Criterion criterion,
                    const FootOptions& options);
ScoreMap tiltMapOf(const FootprintStatistics& stats);

}  // namespace ambler::footfall
