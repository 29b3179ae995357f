#pragma once
// One ISA's half of the packet ops' test: every op of tests/packet_ops.hpp at a packet width,
// run over a block of lanes packet by packet. Included by the ISA's generated translation unit
// (tests/packet_ops_isa.cpp.in) after its packet header, inside its namespace and flags; it uses
// nothing but the packet types, so no code of this ISA leaks into the test's own.
#include "packet_ops.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The lanes first .. first + W - 1 of the inputs, as packets. Integers are loaded by a gather at
// the lane numbers (the packet types have no integer load).
template <int W>
struct InputPackets {
  vfloat<W> a, b;
  vint<W> i, j;
  vbool<W> m, n;
  InputPackets(const test::OpInputs& in, int first)
      : a(vfloat<W>::load(in.a + first)),
        b(vfloat<W>::load(in.b + first)),
        i(gather(in.i + first, to_int(vfloat<W>::load(in.lane)))),
        j(gather(in.j + first, to_int(vfloat<W>::load(in.lane)))),
        m(vfloat<W>(0.5f) < vfloat<W>::load(in.m + first)),
        n(vfloat<W>(0.5f) < vfloat<W>::load(in.n + first)) {}
};

template <int D>
struct DoublePackets {
  vdouble<D> x, y;
  vboold<D> md, nd;
  DoublePackets(const test::OpInputs& in, int first)
      : x(vdouble<D>::load(in.x + first)),
        y(vdouble<D>::load(in.y + first)),
        md(vdouble<D>(0.5) < vdouble<D>::load(in.md + first)),
        nd(vdouble<D>(0.5) < vdouble<D>::load(in.nd + first)) {}
};

template <int W>
void put(vfloat<W> r, test::OpOutputs& out, int first) {
  r.store(out.f + first);
}
template <int W>
void put(vint<W> r, test::OpOutputs& out, int first) {
  r.store(out.i + first);
}
template <int W>
void put(vbool<W> r, test::OpOutputs& out, int first) {
  select(r, vfloat<W>(1.0f), vfloat<W>(0.0f)).store(out.m + first);
}
template <int D>
void put(vdouble<D> r, test::OpOutputs& out, int first) {
  r.store(out.d + first);
}
template <int D>
void put(vboold<D> r, test::OpOutputs& out, int first) {
  select(r, vdouble<D>(1.0), vdouble<D>(0.0)).store(out.d + first);
}

template <int W>
constexpr test::PacketOps make_packet_ops() {
  test::PacketOps ops;
  ops.width = W;
  int next = 0;
#define HEIGHTMARCH_TEST_LANE_OP(name, nan, packet, reference)                     \
  ops.lane_ops[next++] = +[](const test::OpInputs& in, test::OpOutputs& out) {     \
    for (int first = 0; first < test::kOpLanes; first += W) {                      \
      [[maybe_unused]] const auto [a, b, i, j, m, n] = InputPackets<W>(in, first); \
      put<W>(packet, out, first);                                                  \
    }                                                                              \
  };
  HEIGHTMARCH_TEST_LANE_OPS(HEIGHTMARCH_TEST_LANE_OP)
#undef HEIGHTMARCH_TEST_LANE_OP
  ops.reductions = +[](const test::OpInputs& in, test::OpOutputs& out) {
    for (int first = 0; first < test::kOpLanes; first += W) {
      const InputPackets<W> p(in, first);
      const int packet = first / W;
      out.any[packet] = any(p.m);
      out.all[packet] = all(p.m);
      out.none[packet] = none(p.m);
      out.all_true[packet] = all(vbool<W>::all_true());
      out.sum[packet] = reduce_add(gather(in.count + first, to_int(vfloat<W>::load(in.lane))));
      out.smallest[packet] = reduce_min(p.i);
    }
  };
  ops.memory = +[](const test::OpInputs& in, test::OpOutputs& out) {
    for (int first = 0; first < test::kOpLanes; first += W) {
      const vint<W> lanes = to_int(vfloat<W>::load(in.lane));
      const vint<W> index = gather(in.index + first, lanes);
      gather(in.texels, index).store(out.gathered + first);
      gather(in.ints, index).store(out.gathered_int + first);
      vfloat<W> first_texel, second_texel;
      gather_pairs(in.texels, index, first_texel, second_texel);
      first_texel.store(out.first + first);
      second_texel.store(out.second + first);
      vfloat<W> t00, t10, t01, t11;
      fetch_taps(in.texels, test::kTexelStride, test::kTexelRows, gather(in.tx + first, lanes),
                 gather(in.ty + first, lanes), t00, t10, t01, t11);
      t00.store(out.taps[0] + first);
      t10.store(out.taps[1] + first);
      t01.store(out.taps[2] + first);
      t11.store(out.taps[3] + first);
      vfloat<W> kept_a = vfloat<W>::load(in.a + first), kept_b = vfloat<W>::load(in.b + first);
      register_pairs(index, kept_a, kept_b);
      kept_a.store(out.kept[0] + first);
      kept_b.store(out.kept[1] + first);
      store_bytes(gather(in.count + first, lanes) & vint<W>(255), out.bytes + first);
      Table16<float> table;
      Table16<std::int32_t> int_table;
      for (int e = 0; e < 16; ++e) {
        table.values[e] = in.table[e];
        int_table.values[e] = in.int_table[e];
      }
      const vint<W> entry = gather(in.count + first, lanes) & vint<W>(15);
      lookup(table, entry).store(out.looked_up + first);
      lookup(int_table, entry).store(out.looked_up_int + first);
    }
  };
  ops.moves = +[](const test::OpInputs& in, test::OpOutputs& out) {
    for (int first = 0; first < test::kOpLanes; first += W) {
      const InputPackets<W> p(in, first);
      out.bits[first / W] = mask_bits(p.m);
      vint<W>::load(in.i + first).store(out.loaded_int + first);
      // From the texture: element k to the m lane of rank k.
      expand_load(in.texels + first, p.m, p.a).store(out.expanded + first);
      expand_load(in.ints + first, p.m, p.i).store(out.expanded_int + first);
      compress_store(out.compressed + first, p.m, p.a);
      compress_store(out.compressed_int + first, p.m, p.i);
      // Lane l to element first + W - 1 - l.
      const vint<W> reversed = vint<W>(first + W - 1) - to_int(vfloat<W>::load(in.lane));
      scatter(out.scattered, reversed, p.m, p.a);
      scatter(out.scattered_int, reversed, p.m, p.i);
    }
  };
  return ops;
}

template <int D>
constexpr test::DoubleOps make_double_ops() {
  test::DoubleOps ops;
  ops.width = D;
  int next = 0;
#define HEIGHTMARCH_TEST_DOUBLE_OP(name, nan, packet, reference)                \
  ops.lane_ops[next++] = +[](const test::OpInputs& in, test::OpOutputs& out) {  \
    for (int first = 0; first < test::kOpLanes; first += D) {                   \
      [[maybe_unused]] const auto [x, y, md, nd] = DoublePackets<D>(in, first); \
      put<D>(packet, out, first);                                               \
    }                                                                           \
  };
  HEIGHTMARCH_TEST_DOUBLE_OPS(HEIGHTMARCH_TEST_DOUBLE_OP)
#undef HEIGHTMARCH_TEST_DOUBLE_OP
  ops.any_and_store_float = +[](const test::OpInputs& in, test::OpOutputs& out) {
    for (int first = 0; first < test::kOpLanes; first += D) {
      const DoublePackets<D> p(in, first);
      out.any_d[first / D] = any(p.md);
      p.x.store(out.narrowed + first);
    }
  };
  return ops;
}

// The ISA's native width and its widest kernel width (a pair of native packets, where it keeps
// two in flight), and its doubles.
template <int NATIVE_W, int WIDEST_W>
constexpr test::PacketOpTables make_packet_op_tables() {
  test::PacketOpTables tables;
  tables.widths[tables.count++] = make_packet_ops<NATIVE_W>();
  if constexpr (WIDEST_W != NATIVE_W) tables.widths[tables.count++] = make_packet_ops<WIDEST_W>();
  tables.doubles = make_double_ops<kDoubleWidth>();
  return tables;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
