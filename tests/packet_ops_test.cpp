// Every op of the packet types, at every ISA of the list the CPU runs (at its native width and its
// pair's) and for its doubles, against the scalar op of src/simd/packet.hpp's contract, lane by
// lane on random blocks that mix NaNs, infinities, signed zeros, denormals, out-of-range values
// for to_int and equal operands (Highway's habit). The ISA list comes from heightmarch/isa_list.hpp:
// a new ISA is tested without editing this file.
#include "packet_ops.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>

#include "heightmarch/isa.hpp"
#include "test_support.hpp"

namespace heightmarch {

// Each ISA's half, generated from tests/packet_ops_isa.cpp.in.
#define HEIGHTMARCH_DECLARE_PACKET_OPS(id, ...)     \
  namespace isa_##id {                              \
    const test::PacketOpTables& packet_op_tables(); \
  }
HEIGHTMARCH_ISAS(HEIGHTMARCH_DECLARE_PACKET_OPS)
#undef HEIGHTMARCH_DECLARE_PACKET_OPS

namespace {

using test::kOpLanes;

const test::PacketOpTables& tables_of(Isa isa) {
#define HEIGHTMARCH_TABLES_OF(id, ...) \
  if (isa == Isa::id) return isa_##id::packet_op_tables();
  HEIGHTMARCH_ISAS(HEIGHTMARCH_TABLES_OF)
#undef HEIGHTMARCH_TABLES_OF
  throw std::logic_error("no packet ops for an ISA of the list");
}

// The contract's to_int.
std::int32_t truncate_or_int32_min(float a) {
  return a >= -2147483648.0f && a < 2147483648.0f ? static_cast<std::int32_t>(a) : INT32_MIN;
}

template <class T>
std::string show(T value) {
  std::ostringstream text;
  if constexpr (std::is_floating_point_v<T>)
    text << std::hexfloat << value;
  else
    text << +value;
  return text.str();
}

enum class Nan { exact, any_nan };

// Equal bits; with Nan::any_nan, also any NaN for a NaN.
template <class T>
bool same(T got, T want, Nan nan) {
  if constexpr (std::is_floating_point_v<T>) {
    if (nan == Nan::any_nan && std::isnan(want)) return std::isnan(got);
    return std::memcmp(&got, &want, sizeof got) == 0;
  } else {
    return got == want;
  }
}

// Random blocks: a quarter of the lanes special values, a quarter random bits, half small
// numbers (varied floors and ceilings), some operands equal. Masks by block: all false, all
// true, random, or all but one of the same value.
class Lanes {
 public:
  explicit Lanes(std::uint64_t seed) : rng_(seed) {}

  void fill(test::OpInputs& in, int round) {
    for (int k = 0; k < kOpLanes; ++k) {
      in.a[k] = any_float();
      in.b[k] = pick(8) == 0 ? in.a[k] : pick(16) == 0 ? -in.a[k] : any_float();
      in.i[k] = any_int();
      in.j[k] = pick(8) == 0 ? in.i[k] : any_int();
      in.count[k] = std::int32_t(rng_.next() & 0xfffff);
      in.x[k] = pick(8) == 0 ? double(in.a[k]) : any_double();
      in.y[k] = pick(8) == 0 ? in.x[k] : pick(16) == 0 ? -in.x[k] : any_double();
      in.lane[k] = float(k);
    }
    fill_mask(in.m, round);
    fill_mask(in.n, round / 5);
    float md[kOpLanes], nd[kOpLanes];
    fill_mask(md, round / 25);
    fill_mask(nd, round);
    for (int k = 0; k < kOpLanes; ++k) {
      in.md[k] = md[k];
      in.nd[k] = nd[k];
    }
    for (int t = 0; t < test::kTexelStride * test::kTexelRows; ++t) {
      in.texels[t] = float(rng_.uniform());
      in.ints[t] = any_int();
    }
    for (int e = 0; e < 16; ++e) {
      in.table[e] = any_float();
      in.int_table[e] = any_int();
    }
  }

  // Indices for the gathers; fetch_taps' taps, by round: near the first lane's of each packet of
  // `width` (AVX-512's window path), anywhere, or in the first lane's row within 7 columns right
  // of it (AVX2's window path).
  void fill_indices(test::OpInputs& in, int width, int round) {
    const int texels = test::kTexelStride * test::kTexelRows;
    for (int k = 0; k < kOpLanes; ++k) {
      in.index[k] = std::int32_t(rng_.next() % (texels - 1));
      const int lead = k - k % width;
      if (round % 3 == 1 || k == lead) {
        in.tx[k] = std::int32_t(rng_.next() % (test::kTexelStride - 1));
        in.ty[k] = std::int32_t(rng_.next() % (test::kTexelRows - 1));
      } else if (round % 3 == 0) {
        in.tx[k] = std::clamp(in.tx[lead] + int(rng_.next() % 7) - 2, 0, test::kTexelStride - 2);
        in.ty[k] = std::clamp(in.ty[lead] + int(rng_.next() % 4) - 3, 0, test::kTexelRows - 2);
      } else {
        in.tx[k] = std::min(in.tx[lead] + int(rng_.next() % 7), test::kTexelStride - 2);
        in.ty[k] = in.ty[lead];
      }
    }
  }

 private:
  std::uint64_t pick(std::uint64_t n) { return rng_.next() % n; }

  float any_float() {
    static const float special[] = {std::numeric_limits<float>::quiet_NaN(),
                                    -std::numeric_limits<float>::quiet_NaN(),
                                    std::numeric_limits<float>::infinity(),
                                    -std::numeric_limits<float>::infinity(),
                                    0.0f,
                                    -0.0f,
                                    0.5f,
                                    -0.5f,
                                    1.0f,
                                    -1.0f,
                                    1.5f,
                                    -2.5f,
                                    2147483648.0f,
                                    -2147483648.0f,
                                    2147483520.0f,
                                    -2147483904.0f,
                                    16777217.0f,
                                    1e10f,
                                    -1e10f,
                                    std::numeric_limits<float>::max(),
                                    -std::numeric_limits<float>::max(),
                                    std::numeric_limits<float>::denorm_min(),
                                    -1e-40f,
                                    std::numeric_limits<float>::min()};
    switch (pick(4)) {
      case 0:
        return special[pick(std::size(special))];
      case 1: {
        const std::uint32_t bits = std::uint32_t(rng_.next());
        float f;
        std::memcpy(&f, &bits, sizeof f);
        return f;
      }
      default:
        return float(rng_.uniform(-8.0, 8.0));
    }
  }

  double any_double() {
    static const double special[] = {std::numeric_limits<double>::quiet_NaN(),
                                     -std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(),
                                     0.0,
                                     -0.0,
                                     0.5,
                                     -0.5,
                                     1.0,
                                     -1.0,
                                     1e300,
                                     -1e-310,
                                     3.4028235677973366e38,
                                     std::numeric_limits<double>::denorm_min()};
    switch (pick(4)) {
      case 0:
        return special[pick(std::size(special))];
      case 1: {
        const std::uint64_t bits = rng_.next();
        double d;
        std::memcpy(&d, &bits, sizeof d);
        return d;
      }
      default:
        return rng_.uniform(-8.0, 8.0);
    }
  }

  std::int32_t any_int() {
    static const std::int32_t special[] = {0, 1, -1, 2, INT32_MIN, INT32_MAX, 46341, -46341, 65536, 255};
    switch (pick(4)) {
      case 0:
        return special[pick(std::size(special))];
      case 1:
        return std::int32_t(std::uint32_t(rng_.next()));
      default:
        return std::int32_t(pick(2001)) - 1000;
    }
  }

  void fill_mask(float* mask, int mode) {
    const int odd_one = int(pick(kOpLanes));
    for (int k = 0; k < kOpLanes; ++k) {
      switch (mode % 5) {
        case 0:
          mask[k] = 0.0f;
          break;
        case 1:
          mask[k] = 1.0f;
          break;
        case 2:
          mask[k] = float(pick(2));
          break;
        case 3:
          mask[k] = k == odd_one ? 0.0f : 1.0f;
          break;
        default:
          mask[k] = k == odd_one ? 1.0f : 0.0f;
          break;
      }
    }
  }

  test::Random rng_;
};

// Collects the first few mismatches of one op for the failure message.
class Mismatches {
 public:
  explicit Mismatches(std::string where) : where_(std::move(where)) {}
  void add(const std::string& op, int lane, const std::string& inputs, const std::string& got,
           const std::string& want) {
    if (count_++ < 8)
      text_ += "\n  " + where_ + " " + op + " lane " + std::to_string(lane) + ": " + inputs + " gives " +
               got + ", the contract " + want;
  }
  int count() const { return count_; }
  const std::string& text() const { return text_; }

 private:
  std::string where_, text_;
  int count_ = 0;
};

constexpr int kRounds = 400;

void check_lane_ops(const test::PacketOps& ops, const test::OpInputs& in, Mismatches& bad) {
  test::OpOutputs out{};
  int op = 0;
  // Each op's output slot follows from its scalar result's type.
  auto got_of = [&](auto want, int k) {
    using T = decltype(want);
    if constexpr (std::is_same_v<T, bool>)
      return out.m[k] != 0.0f;
    else if constexpr (std::is_same_v<T, float>)
      return out.f[k];
    else
      return out.i[k];
  };
#define HEIGHTMARCH_CHECK_LANE_OP(name, nan, packet, reference)                                        \
  ops.lane_ops[op++](in, out);                                                                         \
  for (int k = 0; k < kOpLanes; ++k) {                                                                 \
    [[maybe_unused]] const float a = in.a[k], b = in.b[k];                                             \
    [[maybe_unused]] const std::int32_t i = in.i[k], j = in.j[k];                                      \
    [[maybe_unused]] const bool m = in.m[k] != 0.0f, n = in.n[k] != 0.0f;                              \
    const auto want = reference;                                                                       \
    const auto got = got_of(want, k);                                                                  \
    if (!same(got, want, Nan::nan))                                                                    \
      bad.add(#name, k,                                                                                \
              "a=" + show(a) + " b=" + show(b) + " i=" + show(i) + " j=" + show(j) + " m=" + show(m) + \
                  " n=" + show(n),                                                                     \
              show(got), show(want));                                                                  \
  }
  HEIGHTMARCH_TEST_LANE_OPS(HEIGHTMARCH_CHECK_LANE_OP)
#undef HEIGHTMARCH_CHECK_LANE_OP
}

void check_reductions_and_memory(const test::PacketOps& ops, const test::OpInputs& in, Mismatches& bad) {
  test::OpOutputs out{};
  ops.reductions(in, out);
  ops.memory(in, out);
  const int w = ops.width;
  for (int first = 0; first < kOpLanes; first += w) {
    bool any = false, all = true;
    std::uint32_t sum = 0;
    std::int32_t smallest = in.i[first];
    for (int k = first; k < first + w; ++k) {
      any = any || in.m[k] != 0.0f;
      all = all && in.m[k] != 0.0f;
      sum += std::uint32_t(in.count[k]);
      smallest = std::min(smallest, in.i[k]);
    }
    const int packet = first / w;
    const std::string lanes = "lanes " + std::to_string(first) + "..";
    if (out.any[packet] != any) bad.add("any", first, lanes, show(out.any[packet]), show(any));
    if (out.all[packet] != all) bad.add("all", first, lanes, show(out.all[packet]), show(all));
    if (out.none[packet] != !any) bad.add("none", first, lanes, show(out.none[packet]), show(!any));
    if (!out.all_true[packet]) bad.add("all_true", first, lanes, "not all", "all");
    if (out.sum[packet] != sum) bad.add("reduce_add", first, lanes, show(out.sum[packet]), show(sum));
    if (out.smallest[packet] != smallest)
      bad.add("reduce_min", first, lanes, show(out.smallest[packet]), show(smallest));
  }
  for (int k = 0; k < kOpLanes; ++k) {
    const std::int32_t index = in.index[k];
    const std::string at = "index=" + show(index);
    auto expect = [&](const char* op, float got, float want, const std::string& inputs) {
      if (!same(got, want, Nan::exact)) bad.add(op, k, inputs, show(got), show(want));
    };
    expect("gather", out.gathered[k], in.texels[index], at);
    if (out.gathered_int[k] != in.ints[index])
      bad.add("gather (int32)", k, at, show(out.gathered_int[k]), show(in.ints[index]));
    expect("gather_pairs first", out.first[k], in.texels[index], at);
    expect("gather_pairs second", out.second[k], in.texels[index + 1], at);
    const std::int32_t tap = in.ty[k] * test::kTexelStride + in.tx[k];
    const std::string xy = "tx=" + show(in.tx[k]) + " ty=" + show(in.ty[k]);
    expect("fetch_taps t00", out.taps[0][k], in.texels[tap], xy);
    expect("fetch_taps t10", out.taps[1][k], in.texels[tap + 1], xy);
    expect("fetch_taps t01", out.taps[2][k], in.texels[tap + test::kTexelStride], xy);
    expect("fetch_taps t11", out.taps[3][k], in.texels[tap + test::kTexelStride + 1], xy);
    expect("register_pairs first", out.kept[0][k], in.a[k], "a=" + show(in.a[k]));
    expect("register_pairs second", out.kept[1][k], in.b[k], "b=" + show(in.b[k]));
    const int entry = in.count[k] & 15;
    expect("lookup", out.looked_up[k], in.table[entry], "entry=" + show(entry));
    if (out.looked_up_int[k] != in.int_table[entry])
      bad.add("lookup (int32)", k, "entry=" + show(entry), show(out.looked_up_int[k]),
              show(in.int_table[entry]));
    if (out.bytes[k] != std::uint8_t(in.count[k] & 255))
      bad.add("store_bytes", k, "count=" + show(in.count[k]), show(out.bytes[k]), show(in.count[k] & 255));
  }
}

// mask_bits, the integer load, expand_load, compress_store and scatter, packet by packet.
void check_moves(const test::PacketOps& ops, const test::OpInputs& in, Mismatches& bad) {
  test::OpOutputs out{};
  ops.moves(in, out);
  const int w = ops.width;
  for (int first = 0; first < kOpLanes; first += w) {
    std::uint32_t bits = 0;
    int rank = 0;  // true lanes so far
    for (int k = first; k < first + w; ++k) {
      const bool m = in.m[k] != 0.0f;
      const std::string lane = "m=" + show(m);
      if (out.loaded_int[k] != in.i[k]) bad.add("vint load", k, "", show(out.loaded_int[k]), show(in.i[k]));
      const float expanded = m ? in.texels[first + rank] : in.a[k];
      if (!same(out.expanded[k], expanded, Nan::exact))
        bad.add("expand_load", k, lane, show(out.expanded[k]), show(expanded));
      const std::int32_t expanded_int = m ? in.ints[first + rank] : in.i[k];
      if (out.expanded_int[k] != expanded_int)
        bad.add("expand_load (int32)", k, lane, show(out.expanded_int[k]), show(expanded_int));
      const int mirror = first + w - 1 - (k - first);
      const float scattered = m ? in.a[k] : 0.0f;
      if (!same(out.scattered[mirror], scattered, Nan::exact))
        bad.add("scatter", k, lane, show(out.scattered[mirror]), show(scattered));
      const std::int32_t scattered_int = m ? in.i[k] : 0;
      if (out.scattered_int[mirror] != scattered_int)
        bad.add("scatter (int32)", k, lane, show(out.scattered_int[mirror]), show(scattered_int));
      if (m) {
        bits |= 1u << (k - first);
        if (!same(out.compressed[first + rank], in.a[k], Nan::exact))
          bad.add("compress_store", k, lane, show(out.compressed[first + rank]), show(in.a[k]));
        if (out.compressed_int[first + rank] != in.i[k])
          bad.add("compress_store (int32)", k, lane, show(out.compressed_int[first + rank]), show(in.i[k]));
        ++rank;
      }
    }
    if (out.bits[first / w] != bits)
      bad.add("mask_bits", first, "lanes " + std::to_string(first) + "..", show(out.bits[first / w]),
              show(bits));
  }
}

void check_double_ops(const test::DoubleOps& ops, const test::OpInputs& in, Mismatches& bad) {
  test::OpOutputs out{};
  int op = 0;
  auto got_of = [&](auto want, int k) {
    using T = decltype(want);
    if constexpr (std::is_same_v<T, bool>)
      return out.d[k] != 0.0;
    else
      return out.d[k];
  };
#define HEIGHTMARCH_CHECK_DOUBLE_OP(name, nan, packet, reference)                                         \
  ops.lane_ops[op++](in, out);                                                                            \
  for (int k = 0; k < kOpLanes; ++k) {                                                                    \
    [[maybe_unused]] const float a = in.a[k];                                                             \
    [[maybe_unused]] const double x = in.x[k], y = in.y[k];                                               \
    [[maybe_unused]] const bool md = in.md[k] != 0.0, nd = in.nd[k] != 0.0;                               \
    const auto want = reference;                                                                          \
    const auto got = got_of(want, k);                                                                     \
    if (!same(got, want, Nan::nan))                                                                       \
      bad.add(#name, k,                                                                                   \
              "a=" + show(a) + " x=" + show(x) + " y=" + show(y) + " md=" + show(md) + " nd=" + show(nd), \
              show(got), show(want));                                                                     \
  }
  HEIGHTMARCH_TEST_DOUBLE_OPS(HEIGHTMARCH_CHECK_DOUBLE_OP)
#undef HEIGHTMARCH_CHECK_DOUBLE_OP
  ops.any_and_store_float(in, out);
  for (int first = 0; first < kOpLanes; first += ops.width) {
    bool any = false;
    for (int k = first; k < first + ops.width; ++k) any = any || in.md[k] != 0.0;
    if (out.any_d[first / ops.width] != any)
      bad.add("any (doubles)", first, "lanes " + std::to_string(first) + "..",
              show(out.any_d[first / ops.width]), show(any));
  }
  for (int k = 0; k < kOpLanes; ++k)
    if (!same(out.narrowed[k], float(in.x[k]), Nan::any_nan))
      bad.add("store to float", k, "x=" + show(in.x[k]), show(out.narrowed[k]), show(float(in.x[k])));
}

class PacketOpsTest : public ::testing::TestWithParam<Isa> {};

TEST_P(PacketOpsTest, EveryOpMatchesTheScalarContract) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa))
    GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": its packet ops are not tested here";
  const test::PacketOpTables& tables = tables_of(isa);
  Lanes lanes(0x5eed0000u + std::uint64_t(isa));
  test::OpInputs in{};
  for (int t = 0; t < tables.count; ++t) {
    const test::PacketOps& ops = tables.widths[t];
    Mismatches bad(to_string(isa) + " vfloat<" + std::to_string(ops.width) + ">");
    for (int round = 0; round < kRounds; ++round) {
      lanes.fill(in, round);
      lanes.fill_indices(in, ops.width, round);
      check_lane_ops(ops, in, bad);
      check_reductions_and_memory(ops, in, bad);
      check_moves(ops, in, bad);
    }
    EXPECT_EQ(bad.count(), 0) << bad.text();
  }
  Mismatches bad(to_string(isa) + " vdouble<" + std::to_string(tables.doubles.width) + ">");
  for (int round = 0; round < kRounds; ++round) {
    lanes.fill(in, round);
    check_double_ops(tables.doubles, in, bad);
  }
  EXPECT_EQ(bad.count(), 0) << bad.text();
}

INSTANTIATE_TEST_SUITE_P(EveryIsaOfTheList, PacketOpsTest, ::testing::ValuesIn(all_isas()),
                         [](const ::testing::TestParamInfo<Isa>& info) {
                           return std::string(isa_id(info.param));
                         });

}  // namespace
}  // namespace heightmarch
