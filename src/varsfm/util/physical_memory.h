#pragma once
// The machine's memory, for the defaults of the stages that bound what they hold at once.
#include <cstddef>

namespace varsfm {

// Physical memory in bytes; 0 where the system does not say.
size_t PhysicalMemoryBytes();

}  // namespace varsfm
