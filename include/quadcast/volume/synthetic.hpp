// quadcast/volume/synthetic.hpp -- synthetic test volumes: Marschner-Lobb and the 3-D Franke function
#pragma once

#include "quadcast/volume/volume.hpp"

namespace quadcast::volume {

/// The Marschner-Lobb test signal (Marschner & Lobb, Vis 1994) with the standard parameters
/// f_M = 6, alpha = 1/4:
///     rho(x,y,z) = (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_M cos(pi r / 2)))) / (2 (1 + alpha)),
///     r = sqrt(x^2 + y^2),
/// with values in [0, 1]; the usual isovalue is 0.5. Evaluated in double.
double marschner_lobb(double x, double y, double z);

/// The 3-D Franke function on [0,1]^3 (the trivariate extension of Franke 1979 used by the
/// spline literature):
///     3/4 exp(-((9x-2)^2 + (9y-2)^2 + (9z-2)^2)/4) + 3/4 exp(-(9x+1)^2/49 - (9y+1)/10 - (9z+1)/10)
///   + 1/2 exp(-((9x-7)^2 + (9y-3)^2 + (9z-5)^2)/4) - 1/5 exp(-(9x-4)^2 - (9y-7)^2 - (9z-5)^2).
double franke3(double x, double y, double z);

/// n^3 samples of marschner_lobb on [-1,1]^3 (spacing 2/(n-1), origin -1; the classic
/// sampling is n = 41). n >= 2.
VolumeData marschner_lobb_volume(int n);

/// n^3 samples of franke3 on [0,1]^3 (spacing 1/(n-1), origin 0). n >= 2.
VolumeData franke_volume(int n);

}  // namespace quadcast::volume
