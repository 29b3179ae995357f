#include "heightmarch/memory_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch {

std::size_t parse_memory_limit(const std::string& text, const std::string& name) {
  constexpr double kLargest = 4611686018427387904.0;  // 2^62: far beyond any machine, and exact in a double
  const auto refuse = [&](const std::string& why) -> std::size_t {
    throw InputError(name + "='" + text + "': " + why +
                     " (bytes, or a number with a suffix K, M, G or T, powers of 1024: 512M, 1.5G)");
  };
  std::size_t i = 0;
  double value = 0.0;
  std::size_t digits = 0;
  // Digits, then an optional fraction; a double holds 2^62 exactly and the fraction's rounding is
  // below a byte at any scale that passes the bound below.
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) && digits < 40) {
    value = value * 10.0 + (text[i++] - '0');
    ++digits;
  }
  if (i < text.size() && text[i] == '.') {
    double unit = 0.1;
    for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) && digits < 40;
         ++i, ++digits) {
      value += (text[i] - '0') * unit;
      unit /= 10.0;
    }
  }
  if (digits == 0) return refuse("not a size");
  if (digits == 40) return refuse("too many digits");
  std::string suffix = text.substr(i);
  for (char& c : suffix) c = char(std::toupper(static_cast<unsigned char>(c)));
  double scale = 1.0;
  if (suffix != "" && suffix != "B") {
    static const char* const units = "KMGT";
    const char* unit = suffix.size() <= 3 ? std::strchr(units, suffix[0]) : nullptr;
    const std::string tail = suffix.substr(1);
    if (!unit || !*unit || !(tail.empty() || tail == "B" || tail == "IB"))
      return refuse("unknown suffix '" + text.substr(i) + "'");
    for (const char* u = units; u <= unit; ++u) scale *= 1024.0;
  }
  const double bytes = std::floor(value * scale);
  if (bytes < 1.0) return refuse("a budget of 0 bytes");
  if (bytes > kLargest) return refuse("more than 2^62 bytes");
  return std::size_t(bytes);
}

namespace {

// set_memory_budget's: 0 until called (once, at start-up, before other threads run).
std::size_t g_set_budget = 0;
std::string g_set_source;

}  // namespace

void set_memory_budget(std::size_t bytes, const std::string& source) {
  g_set_budget = bytes;
  g_set_source = source;
}

std::size_t memory_budget() {
  if (g_set_budget) return g_set_budget;
  // Set but empty is unset, as a shell's `HEIGHTMARCH_MEMORY_LIMIT=` means.
  if (const char* limit = std::getenv("HEIGHTMARCH_MEMORY_LIMIT"); limit && *limit)
    return parse_memory_limit(limit);
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? std::size_t(pages) * std::size_t(page) / 2 : std::size_t(4) << 30;
}

std::string memory_budget_source() {
  if (g_set_budget) return g_set_source;
  if (const char* limit = std::getenv("HEIGHTMARCH_MEMORY_LIMIT"); limit && *limit)
    return "HEIGHTMARCH_MEMORY_LIMIT";
  return "half the RAM";
}

ProcessMemory process_memory() {
  // statm, in pages: size, resident, shared, text, lib (unused), data (+ stack).
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (!statm) return {};
  unsigned long long pages[6] = {};
  const bool read = std::fscanf(statm, "%llu %llu %llu %llu %llu %llu", &pages[0], &pages[1], &pages[2],
                                &pages[3], &pages[4], &pages[5]) == 6;
  std::fclose(statm);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (!read || page <= 0) return {};
  return {std::size_t(pages[1]) * std::size_t(page), std::size_t(pages[5]) * std::size_t(page)};
}

std::size_t memory_budget_left() {
  const std::size_t budget = memory_budget(), held = resident_bytes();
  return budget > held ? budget - held : 0;
}

std::string bytes_text(double bytes) {
  if (bytes < 1024.0) return std::to_string((long long)bytes) + " bytes";
  const char* const units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  for (bytes /= 1024.0; bytes >= 1024.0 && unit < 5; bytes /= 1024.0) ++unit;
  char text[48];
  std::snprintf(text, sizeof text, "%.1f %s", bytes, units[unit]);
  return text;
}

void check_memory_budget(double bytes, const std::string& what) {
  const double budget = double(memory_budget()), held = double(resident_bytes());
  if (held + bytes <= budget) return;
  throw InputError(what + " needs " + bytes_text(bytes) + ", more than the " +
                   bytes_text(std::max(0.0, budget - held)) + " left of the " + bytes_text(budget) +
                   " budget (" + memory_budget_source() + "; " + bytes_text(held) + " already in use)");
}

void check_memory_budget_covers_footprint(const std::string& program) {
  const double budget = double(memory_budget()), held = double(resident_bytes());
  if (held < budget) return;
  throw InputError("a memory budget of " + bytes_text(budget) + " (" + memory_budget_source() +
                   ") is below " + program + "'s own footprint of " + bytes_text(held) +
                   " (its code and the libraries it loads, resident before any input)");
}

}  // namespace heightmarch
