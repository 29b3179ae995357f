#pragma once
// The packet ops under test as plain data: a block of input lanes, a block of output lanes and
// one function per op. Each ISA's half (tests/packet_ops_isa.hpp, compiled per ISA from
// tests/packet_ops_isa.cpp.in) fills a table of such functions; tests/packet_ops_test.cpp runs
// them on random lanes and compares every lane with the scalar op of src/simd/packet.hpp's
// contract. Only these structs and function pointers cross between the two.
#include <cstdint>

namespace heightmarch::test {

inline constexpr int kOpLanes = 64;                       // one block: a multiple of every packet width
inline constexpr int kTexelStride = 37, kTexelRows = 23;  // the gathers' texture (odd sizes)

struct OpInputs {
  float a[kOpLanes], b[kOpLanes];
  float m[kOpLanes], n[kOpLanes];  // masks: 0 or 1
  std::int32_t i[kOpLanes], j[kOpLanes];
  std::int32_t count[kOpLanes];  // reduce_add's: 0 .. 2^20; store_bytes takes the low byte
  double x[kOpLanes], y[kOpLanes];
  double md[kOpLanes], nd[kOpLanes];  // masks of doubles: 0 or 1
  float texels[kTexelStride * kTexelRows];
  std::int32_t ints[kTexelStride * kTexelRows];
  std::int32_t index[kOpLanes];             // gather: inside the texture; gather_pairs: index + 1 too
  std::int32_t tx[kOpLanes], ty[kOpLanes];  // fetch_taps: (tx + 1, ty + 1) inside the texture
  float table[16];                          // lookup's, at count & 15
  std::int32_t int_table[16];
  float lane[kOpLanes];  // 0, 1, 2, ...: the packets' lane numbers
};

struct OpOutputs {
  float f[kOpLanes];
  std::int32_t i[kOpLanes];
  float m[kOpLanes];  // a mask: 0 or 1
  double d[kOpLanes];
  // per packet (at first lane / width)
  bool any[kOpLanes], all[kOpLanes], none[kOpLanes], all_true[kOpLanes], any_d[kOpLanes];
  std::uint32_t sum[kOpLanes];
  std::int32_t smallest[kOpLanes];  // reduce_min of i
  // memory
  std::uint8_t bytes[kOpLanes];
  float gathered[kOpLanes], first[kOpLanes], second[kOpLanes], taps[4][kOpLanes], kept[2][kOpLanes];
  std::int32_t gathered_int[kOpLanes];
  float looked_up[kOpLanes];
  std::int32_t looked_up_int[kOpLanes];
  float narrowed[kOpLanes];  // vdouble stored to float
  // lanes moved (the walks' refill)
  std::uint32_t bits[kOpLanes];  // mask_bits of m, per packet
  std::int32_t loaded_int[kOpLanes];
  float expanded[kOpLanes], compressed[kOpLanes], scattered[kOpLanes];
  std::int32_t expanded_int[kOpLanes], compressed_int[kOpLanes], scattered_int[kOpLanes];
};

using OpFn = void (*)(const OpInputs&, OpOutputs&);

// The ops of vfloat<W>, vint<W>, vbool<W> that act lane by lane:
// X(name, NaN results: exact bits or any NaN, the packet op, the scalar op of the contract).
// Inputs a, b (float), i, j (int32), m, n (mask); the packet side reads them as packets.
#define HEIGHTMARCH_TEST_LANE_OPS(X)                                                           \
  X(identity, exact, a, a)                                                                     \
  X(add, any_nan, a + b, a + b)                                                                \
  X(sub, any_nan, a - b, a - b)                                                                \
  X(mul, any_nan, a* b, a* b)                                                                  \
  X(div, any_nan, a / b, a / b)                                                                \
  X(min, exact, min(a, b), a < b ? a : b)                                                      \
  X(max, exact, max(a, b), a > b ? a : b)                                                      \
  X(abs, exact, abs(a), std::fabs(a))                                                          \
  X(floor, any_nan, floor(a), std::floor(a))                                                   \
  X(ceil, any_nan, ceil(a), std::ceil(a))                                                      \
  X(sqrt, any_nan, sqrt(a), std::sqrt(a))                                                      \
  X(less, exact, a < b, a < b)                                                                 \
  X(greater, exact, a > b, a > b)                                                              \
  X(greater_equal, exact, a >= b, a >= b)                                                      \
  X(not_equal, exact, a != b, a != b)                                                          \
  X(select, exact, select(m, a, b), m ? a : b)                                                 \
  X(to_int, exact, to_int(a), truncate_or_int32_min(a))                                        \
  X(int_add, exact, i + j, std::int32_t(std::uint32_t(i) + std::uint32_t(j)))                  \
  X(int_sub, exact, i - j, std::int32_t(std::uint32_t(i) - std::uint32_t(j)))                  \
  X(int_mul, exact, i* j, std::int32_t(std::uint32_t(i) * std::uint32_t(j)))                   \
  X(int_and, exact, i& j, i& j)                                                                \
  X(int_less, exact, i < j, i < j)                                                             \
  X(int_min, exact, min(i, j), i < j ? i : j)                                                  \
  X(int_max, exact, max(i, j), i > j ? i : j)                                                  \
  X(int_select, exact, select(m, i, j), m ? i : j)                                             \
  X(int_or, exact, i | j, i | j)                                                               \
  X(int_xor, exact, i ^ j, i ^ j)                                                              \
  X(int_equal, exact, i == j, i == j)                                                          \
  X(int_shift_left, exact, i << (j & vint<W>(31)), std::int32_t(std::uint32_t(i) << (j & 31))) \
  X(int_shift_right, exact, i >> (j & vint<W>(31)), i >> (j & 31))                             \
  X(int_shift_left_by_one_count, exact, i << 13, std::int32_t(std::uint32_t(i) << 13))         \
  X(to_float, exact, to_float(i), float(i))                                                    \
  X(mask_to_int, exact, to_int(m), m ? -1 : 0)                                                 \
  X(mask_and_not, exact, and_not(m, n), m && !n)                                               \
  X(pow2, exact, pow2((i & vint<W>(127)) - vint<W>(63)), std::ldexp(1.0f, (i & 127) - 63))     \
  X(mask_and, exact, m& n, m&& n)                                                              \
  X(mask_or, exact, m | n, m || n)                                                             \
  X(mask_not, exact, !m, !m)

// The ops of vdouble<D>, vboold<D> that act lane by lane, as above with inputs x, y (double),
// md, nd (mask) and a (float, for the conversion).
#define HEIGHTMARCH_TEST_DOUBLE_OPS(X)                              \
  X(d_identity, exact, x, x)                                        \
  X(d_from_float, exact, vdouble<D>::load(in.a + first), double(a)) \
  X(d_add, any_nan, x + y, x + y)                                   \
  X(d_sub, any_nan, x - y, x - y)                                   \
  X(d_mul, any_nan, x* y, x* y)                                     \
  X(d_div, any_nan, x / y, x / y)                                   \
  X(d_neg, exact, -x, -x)                                           \
  X(d_less, exact, x < y, x < y)                                    \
  X(d_less_equal, exact, x <= y, x <= y)                            \
  X(d_greater, exact, x > y, x > y)                                 \
  X(d_greater_equal, exact, x >= y, x >= y)                         \
  X(d_equal, exact, x == y, x == y)                                 \
  X(d_not_equal, exact, x != y, x != y)                             \
  X(d_min, exact, min(x, y), std::min(x, y))                        \
  X(d_max, exact, max(x, y), std::max(x, y))                        \
  X(d_abs, exact, abs(x), std::fabs(x))                             \
  X(d_floor, any_nan, floor(x), std::floor(x))                      \
  X(d_sqrt, any_nan, sqrt(x), std::sqrt(x))                         \
  X(d_copysign, exact, copysign(x, y), std::copysign(x, y))         \
  X(d_select, exact, select(md, x, y), md ? x : y)                  \
  X(d_mask_and, exact, md& nd, md&& nd)                             \
  X(d_mask_or, exact, md | nd, md || nd)                            \
  X(d_mask_not, exact, !md, !md)

#define HEIGHTMARCH_TEST_COUNT_OP(...) +1
inline constexpr int kLaneOpCount = 0 HEIGHTMARCH_TEST_LANE_OPS(HEIGHTMARCH_TEST_COUNT_OP);
inline constexpr int kDoubleOpCount = 0 HEIGHTMARCH_TEST_DOUBLE_OPS(HEIGHTMARCH_TEST_COUNT_OP);
#undef HEIGHTMARCH_TEST_COUNT_OP

struct PacketOps {
  int width = 0;
  OpFn lane_ops[kLaneOpCount] = {};  // in HEIGHTMARCH_TEST_LANE_OPS' order
  OpFn reductions = nullptr;         // any, all, none, all_true, reduce_add, reduce_min per packet
  OpFn memory = nullptr;             // the gathers, fetch_taps, register_pairs, store_bytes, lookup
  OpFn moves = nullptr;              // mask_bits, the integer load, expand_load, compress_store, scatter
};

struct DoubleOps {
  int width = 0;
  OpFn lane_ops[kDoubleOpCount] = {};  // in HEIGHTMARCH_TEST_DOUBLE_OPS' order
  OpFn any_and_store_float = nullptr;  // any per packet; each lane stored to float
};

// One ISA's tables: its native width and, where it keeps two packets in flight, the pair's.
struct PacketOpTables {
  int count = 0;
  PacketOps widths[2];
  DoubleOps doubles;
};

}  // namespace heightmarch::test
