// The command-line layer's numbers and usage error, model-independent: moved to the analysis
// layer (mechgen/analysis/numbers.h), which the analyses' checks share with the tools.
#pragma once

#include "mechgen/analysis/numbers.h"
