// quadcast/spline/spline.hpp -- umbrella header of the trivariate spline module (QSS, S31)
#pragma once

#include "quadcast/spline/grid.hpp"
#include "quadcast/spline/masks.hpp"
#include "quadcast/spline/octree.hpp"
#include "quadcast/spline/partition.hpp"
#include "quadcast/spline/quasi_interpolation.hpp"
