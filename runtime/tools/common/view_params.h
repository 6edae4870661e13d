// The parameter options on a model (the generated one or its view): moved to the analysis layer
// (mechgen/analysis/view_params.h).
#pragma once

#include "mechgen/analysis/view_params.h"
