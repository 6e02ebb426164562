// quadcast/quadcast.hpp -- umbrella header of the quadric core (no GL, no I/O)
#pragma once

#include "quadcast/scalar.hpp"
#include "quadcast/linalg.hpp"
#include "quadcast/quadric.hpp"
#include "quadcast/ray.hpp"
#include "quadcast/cull.hpp"
#include "quadcast/bilinear.hpp"
#include "quadcast/primitives.hpp"
#include "quadcast/bounds.hpp"
