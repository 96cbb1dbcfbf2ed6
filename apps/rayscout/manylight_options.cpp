// Options of `rayscout render --integrator manylight`: everything is inline in manylight_options.h
// (the CLI compiles only cmd_*.cpp; integrators.cpp includes the header). This unit only checks
// that the header compiles on its own when a build lists it.
#include "manylight_options.h"
