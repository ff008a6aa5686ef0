#pragma once

#include "sensor/RangeImage.h"
#include "terrain/ElevationMap.h"

namespace ambler::terrain {

// cmu-1990 'LTM Merger': fuses `update` (one view) into `map` (the local
// terrain map) by maximum likelihood. Each cell of `map` takes the update's
// cell under its centre; where both know the height, the result is the
// inverse-variance weighted mean, with 1/sigma^2 = 1/sigma_a^2 + 1/sigma_b^2
// (sigmas below 1 micrometre count as 1 micrometre). A cell known in either
// becomes known, so shadows seen from a later position are filled in; one
// oblique in either and known in neither becomes oblique; shadow wins over
// unknown. Observation counts add. Throws std::invalid_argument
// when the frames differ.
void mergeInto(ElevationMap& map, const ElevationMap& update);

// cmu-1990 'LTM builder' then 'LTM merger': the scan's locus map
// (krotkov1989 §3) over the part of the traverse map its returns fall in,
// fused into it. Returns that part; no cells when the returns miss the map.
GridSpec mergeScan(ElevationMap& traverse, const sensor::RangeImage& scan);

}  // namespace ambler::terrain
