#pragma once
/// The analyses of a silo in one include: Janssen's vertical stress and its fit, Beverloo's
/// discharge rate and its fit, the steady rate of a discharge, wall stresses in bands, the
/// vertical stress in slices, and the lateral pressure ratio.
#include "granular/beverloo.hpp"
#include "granular/discharge_rate.hpp"
#include "granular/janssen.hpp"
#include "granular/lateral_ratio.hpp"
#include "granular/slice_stress.hpp"
#include "granular/wall_bands.hpp"
