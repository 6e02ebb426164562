// quadcast/bb/bb.hpp -- umbrella header of the Bernstein-Bezier module
#pragma once

#include "quadcast/bb/bezier.hpp"
#include "quadcast/bb/multi_index.hpp"
#include "quadcast/bb/restrict.hpp"
#include "quadcast/bb/roots.hpp"
