#pragma once
// A memory budget checked before large allocations (depth maps, ray batches, hits, images), so
// an absurd size is a clear error instead of an out-of-memory kill.
#include <cstddef>
#include <string>

namespace heightmarch {

// Bytes heightmarch may allocate for one structure: $HEIGHTMARCH_MEMORY_LIMIT (bytes, or with a
// K/M/G suffix) if set, else half of the physical memory.
std::size_t memory_budget();

// Throws InputError "<what> needs N MiB, more than the M MiB budget" when bytes exceeds the budget.
void check_memory_budget(double bytes, const std::string& what);

}  // namespace heightmarch
