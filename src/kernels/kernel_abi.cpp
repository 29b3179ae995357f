#include "kernels/kernel_abi.hpp"

#include <stdexcept>
#include <string>

namespace heightmarch {

const KernelTable& kernel_table(Isa isa) {
#define HEIGHTMARCH_ISA_TABLE(id, ...) \
  if (isa == Isa::id) return isa_##id::kernel_table();
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_TABLE)
#undef HEIGHTMARCH_ISA_TABLE
  throw std::logic_error("no kernel table for ISA " + to_string(isa));
}

}  // namespace heightmarch
