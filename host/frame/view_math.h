// view_math.h — the camera math moved to the stages layer (stages/view_math.h), below the
// grooms that use it; this name stays for the frame files that still include it.
#pragma once

#include "stages/view_math.h"
