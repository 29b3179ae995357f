#pragma once
// A memory budget checked before large allocations (depth maps, ray batches and files, hits,
// tiles, images), so an absurd size is a clear error instead of an out-of-memory kill.
#include <cstddef>
#include <string>

namespace heightmarch {

// Bytes heightmarch may allocate for one run's largest structures: $HEIGHTMARCH_MEMORY_LIMIT if
// set (parse_memory_limit), else half of the physical memory. Throws InputError for a malformed
// HEIGHTMARCH_MEMORY_LIMIT.
std::size_t memory_budget();

// A size in bytes: a positive decimal number (digits, an optional fraction) with an optional
// suffix K, M, G or T (powers of 1024, either case, optionally followed by B or iB: 512M, 1.5GiB,
// 2T), at least 1 byte and at most 2^62. Anything else (1e30, inf, nan, -1, 0, 10X, abc) throws
// InputError naming `name`.
std::size_t parse_memory_limit(const std::string& text, const std::string& name = "HEIGHTMARCH_MEMORY_LIMIT");

// Throws InputError "<what> needs N MiB, more than the M MiB budget" when bytes exceeds the budget.
void check_memory_budget(double bytes, const std::string& what);

}  // namespace heightmarch
