#include "heightmarch/memory_budget.hpp"

#include <unistd.h>

#include <cstdlib>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch {

std::size_t memory_budget() {
  if (const char* limit = std::getenv("HEIGHTMARCH_MEMORY_LIMIT")) {
    char* end = nullptr;
    const double value = std::strtod(limit, &end);
    double scale = 1.0;
    if (end && (*end == 'K' || *end == 'k')) scale = 1024.0;
    if (end && (*end == 'M' || *end == 'm')) scale = 1024.0 * 1024.0;
    if (end && (*end == 'G' || *end == 'g')) scale = 1024.0 * 1024.0 * 1024.0;
    if (value > 0) return std::size_t(value * scale);
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? std::size_t(pages) * std::size_t(page) / 2 : std::size_t(4) << 30;
}

void check_memory_budget(double bytes, const std::string& what) {
  const double budget = double(memory_budget());
  if (bytes <= budget) return;
  throw InputError(what + " needs " + std::to_string((long long)(bytes / 1048576.0)) + " MiB, more than the " +
                   std::to_string((long long)(budget / 1048576.0)) + " MiB budget (HEIGHTMARCH_MEMORY_LIMIT)");
}

}  // namespace heightmarch
