// --params FILE and --set name=value: moved to the analysis layer (mechgen/analysis/params.h),
// where a Request carries them.
#pragma once

#include "mechgen/analysis/params.h"
