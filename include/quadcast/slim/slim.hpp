// quadcast/slim/slim.hpp -- the slim component: SLIM surfaces built from oriented point clouds
#pragma once

#include "quadcast/slim/build.hpp"
#include "quadcast/slim/fit.hpp"
#include "quadcast/slim/model.hpp"
#include "quadcast/slim/points.hpp"
#include "quadcast/slim/scene_loader.hpp"
