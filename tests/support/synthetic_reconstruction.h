#pragma once
// Test helper: the synthetic module's ReconstructionFromSynthetic under the name the tests use.
#include "varsfm/synthetic/synthetic_reconstruction.h"

namespace varsfm::testing {

using varsfm::ReconstructionFromSynthetic;

}  // namespace varsfm::testing
