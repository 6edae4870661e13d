// --range read against the model's inputs and the one message for a range whose steps are too
// long: moved to the analysis layer (mechgen/analysis/inputs.h).
#pragma once

#include "mechgen/analysis/inputs.h"
