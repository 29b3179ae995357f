#pragma once
// One memory budget for a process: the most it may hold resident, its own code and libraries
// included. It is asked before every allocation that scales with the input (a depth map and its
// decoder's buffers, ray batches and files, hits, precomputed textures, images, messages of the
// GLSL worker): what the process holds now plus what the allocation needs must fit, so a run over
// budget is a clear error before it allocates instead of an out-of-memory kill at its peak.
#include <cstddef>
#include <string>

namespace heightmarch {

// The budget in bytes: set_memory_budget()'s (--memory-limit) if called, else
// $HEIGHTMARCH_MEMORY_LIMIT if set (parse_memory_limit), else half of the physical memory. Throws
// InputError for a malformed HEIGHTMARCH_MEMORY_LIMIT.
std::size_t memory_budget();

// Where the budget comes from, for messages: "--memory-limit", "HEIGHTMARCH_MEMORY_LIMIT" or
// "half the RAM".
std::string memory_budget_source();

// Sets the budget for the rest of the process (the command line's --memory-limit, or the GLSL
// worker's, which its client gives it); `source` names it in messages.
void set_memory_budget(std::size_t bytes, const std::string& source = "--memory-limit");

// A size in bytes: a positive decimal number (digits, an optional fraction) with an optional
// suffix K, M, G or T (powers of 1024, either case, optionally followed by B or iB: 512M, 1.5GiB,
// 2T), at least 1 byte and at most 2^62. Anything else (1e30, inf, nan, -1, 0, 10X, abc) throws
// InputError naming `name`.
std::size_t parse_memory_limit(const std::string& text, const std::string& name = "HEIGHTMARCH_MEMORY_LIMIT");

// The process's memory now, in bytes, as the system says (0 where it does not): what it holds
// resident (code, libraries and data) and its data as allocated, touched or not (what the OS
// limit RLIMIT_DATA counts).
struct ProcessMemory {
  std::size_t resident = 0;
  std::size_t data = 0;
};
ProcessMemory process_memory();
inline std::size_t resident_bytes() { return process_memory().resident; }

// What the budget leaves beside what the process holds now: memory_budget() - resident_bytes(), or 0.
std::size_t memory_budget_left();

// Throws InputError "<what> needs N, more than the M left of the B budget (R in use ...)" when
// resident_bytes() + bytes exceeds the budget.
void check_memory_budget(double bytes, const std::string& what);

// At start-up, before any input is read: throws InputError when the budget is below what the
// process (`program`: "heightmarch", "the GLSL worker") already holds, naming that footprint.
void check_memory_budget_covers_footprint(const std::string& program);

// 512 bytes, 3.0 KiB, 17.2 MiB, 2.4 GiB, 1.0 TiB.
std::string bytes_text(double bytes);

}  // namespace heightmarch
