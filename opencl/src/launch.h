#pragma once
// The launch helper is public (model/ launches its own kernels); engine sources include it
// under its old local name.
#include "simpli/ocl/launch.h"
