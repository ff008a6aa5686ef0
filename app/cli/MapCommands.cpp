#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "sensor/RangeImageFile.h"
#include "terrain/Binning.h"
#include "terrain/ElevationMapFile.h"
#include "terrain/Locus.h"

namespace ambler::cli {

namespace {

// A length [m] above zero, or inf to turn its rule off. CLI11's
// PositiveNumber refuses inf and lets NaN through.
const CLI::Validator kLengthOrInf(
    [](std::string& text) -> std::string {
      double v = NAN;
      std::size_t used = 0;
      try {
        v = std::stod(text, &used);
      } catch (const std::exception&) {
      }
      if (used != text.size() || !(v > 0))
        return "'" + text + "' is not a length above 0 [m] or inf";
      return {};
    },
    "LENGTH|inf");

struct MapArgs {
  std::string range;
  std::string region;
  double resolution = 0.05;
  std::string out;
  std::string method = "locus";
  terrain::LocusOptions locus;
};

// Where the locus map stops calling ground known because its range noise
// could hide a foot-sized gap [m]; null without noise or for binning.
nlohmann::json obliqueBeyond(const MapArgs& a, const sensor::RangeImage& image) {
  const double range = terrain::rangeWhereNoiseMayHideGap(image.range_sigma_k, a.locus);
  if (a.method != "locus" || !std::isfinite(range)) return nullptr;
  return range;
}

void runMap(const MapArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const auto image = sensor::readRangeImage(a.range);
  const auto grid = gridOver(parseRegion(a.region), a.resolution, "map");
  const auto build_start = std::chrono::steady_clock::now();
  const auto map = a.method == "locus" ? terrain::buildLocusMap(image, grid, a.locus)
                                       : terrain::buildBinnedMap(image, grid);
  const double build_ms = millisecondsSince(build_start);
  terrain::writeElevationMap(map, a.out);
  printJson({{"map", a.out},
             {"method", a.method},
             {"rows", grid.rows},
             {"cols", grid.cols},
             {"resolution", grid.resolution},
             {"known", map.countOf(terrain::CellState::kKnown)},
             {"shadow", map.countOf(terrain::CellState::kShadow)},
             {"unknown", map.countOf(terrain::CellState::kUnknown)},
             {"oblique", map.countOf(terrain::CellState::kOblique)},
             {"oblique_beyond_m", obliqueBeyond(a, image)},
             {"build_ms", build_ms},
             {"elapsed_ms", millisecondsSince(start)}});
}

}  // namespace

void addLocusOptions(CLI::App& cmd, terrain::LocusOptions& locus) {
  auto& edges = locus.edges;
  cmd.add_option("--min-grazing", edges.min_grazing_deg,
                 "range jumps steeper than a surface seen at this grazing angle are occluding "
                 "edges [deg]")
      ->check(CLI::Range(0.1, 45.0))
      ->capture_default_str();
  cmd.add_option("--step-ratio", edges.step_ratio,
                 "and larger than this many times the range change on the occluder's side")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd.add_option("--edge-noise", edges.noise_sigmas,
                 "extra jump allowed for range noise [std. dev.]")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--edge-weak-noise", edges.weak_noise_sigmas,
                 "a smaller allowance [std. dev.] for jumps continued by a neighbouring jump")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--grazing-oblique", edges.mark_grazing,
                 "cells between samples steeper than --min-grazing that are no edge are "
                 "oblique: a height, not to stand on (true/false)")
      ->capture_default_str();
  cmd.add_option("--grazing-noise", edges.grazing_noise_sigmas,
                 "noise allowance [std. dev.] before a pair counts as grazing")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--grazing-weak-noise", edges.weak_grazing_noise_sigmas,
                 "a smaller allowance [std. dev.] for pairs beside a grazing pair or an edge")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--grazing-weak-angle", edges.weak_grazing_deg,
                 "beside a grazing pair or an edge, jumps steeper than a surface seen at this "
                 "larger grazing angle are grazing too [deg]; at most --min-grazing: off")
      ->check(CLI::Range(0.1, 45.0))
      ->capture_default_str();
  cmd.add_option("--grazing-concave-turn", edges.concave_turn_deg,
                 "and so are such jumps whose next pair farther along the column is seen this "
                 "much more steeply, beyond the grazing noise allowance [deg]; 0: off")
      ->check(CLI::Range(0.0, 45.0))
      ->capture_default_str();
  cmd.add_option("--grazing-baseline", edges.grazing_baseline_rows,
                 "scanlines over which the range step is averaged for a second grazing test, "
                 "which noise cannot hide; 0: off")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd.add_option("--grazing-baseline-noise", edges.grazing_baseline_noise_sigmas,
                 "its noise allowance [std. dev. of the averaged step]")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--oblique-shadow-far-ends", locus.oblique_shadow_far_ends,
                 "with --oblique-shadow-sides, so are the known cells one and two steps beyond a "
                 "shadow along the line of sight (true/false)")
      ->capture_default_str();
  cmd.add_option("--oblique-shadow-sides", locus.oblique_shadow_sides,
                 "known cells beside a shadow across the line of sight are oblique (true/false)")
      ->capture_default_str();
  cmd.add_option("--max-sample-spacing", locus.max_sample_spacing_m,
                 "cells between samples farther apart on the ground are unknown [m]; inf: off")
      ->check(kLengthOrInf)
      ->capture_default_str();
  cmd.add_option("--max-gap-hidden-by-noise", locus.max_gap_hidden_by_noise_m,
                 "cells whose range noise could hide a gap in the ground this long from the "
                 "occluding-edge test are oblique [m]; inf: off")
      ->check(kLengthOrInf)
      ->capture_default_str();
  cmd.add_option("--face-side-noise", locus.face_side_noise_sigmas,
                 "cells beside a face across the line of sight whose heights lie beyond this many "
                 "std. dev. of the face's middle have the face in their sigma; 0: off")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  cmd.add_option("--curved-between-scanlines", locus.curved_between_scanlines,
                 "the surface between two scanlines follows a spline through them and the "
                 "scanlines either side, not their chord; false: the paper's bilinear surface "
                 "(true/false)")
      ->capture_default_str();
  cmd.add_option("--undecided-before-shadow", locus.undecided_before_shadow,
                 "shadow cells closer to the occluder's last sample than this many of the "
                 "samples' steps before it are unknown: the edge may lie there [steps]; 0: off")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd.add_option("--undecided-shadow-far-end", locus.undecided_shadow_far_end,
                 "behind a crest, shadow cells in this share of the stretch where the shadow "
                 "may end, nearest the ground's first sample, are unknown; 0: off")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd.add_option("--crest-max-angle", locus.crest_max_angle_deg,
                 "an occluder is a crest when its last two samples lie within this angle of the "
                 "ray through the last; else a face, which may go on unseen [deg]")
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
}

void addMap(CLI::App& app) {
  auto args = std::make_shared<MapArgs>();
  auto* cmd = app.add_subcommand("map", "Build an elevation map from a range image");
  cmd->add_option("--range", args->range, "range image TIFF (with its JSON sidecar)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--region", args->region, "map area XMIN,YMIN,XMAX,YMAX in the world frame [m]")
      ->required();
  cmd->add_option("--resolution", args->resolution, "cell size [m]")
      ->check(CLI::Range(0.001, 10.0))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->add_option("--method", args->method, "locus (krotkov1989 §3) or binning (baseline)")
      ->check(CLI::IsMember({"locus", "binning"}))
      ->capture_default_str();
  cmd->add_option("--threads", args->locus.threads, "threads for the locus method (0: all cores)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  addLocusOptions(*cmd, args->locus);
  cmd->callback([args] { runMap(*args); });
}

}  // namespace ambler::cli
