# The ISAs the packet kernels are compiled for: one list per architecture, narrowest first, and
# the only one. Everything else derives from it (see heightmarch_generate_isas below): the C++ list
# (the generated heightmarch/isa_list.hpp: the Isa enum, names, CPU features, packet widths), one
# kernel and one auto-vectorised translation unit per ISA compiled with its flags, and the tests.
#
# heightmarch_isa(ID NAME HEADER WIDTH MARCH_PACKETS WALK_PACKETS WALK_EVENT_LANES HIGHWAY_TARGET
#                 CPU_FEATURES FLAGS [AUTOVEC_FLAGS])
#   ID: a C++ identifier (its namespace is isa_ID); NAME: on the command line and in results.
#   HEADER: its packet header in src/simd/, which defines vfloat<WIDTH> and friends.
#   MARCH_PACKETS, WALK_PACKETS: native packets in flight per loop iteration (1 or 2, where 2
#     uses src/simd/packet_pair.hpp) for the registry's two kernel shapes (technique_list.hpp).
#     A walk's pass keeps five values a lane in registers: on 16 registers a pair spills and its
#     instructions grow by a fifth, and it walked no faster than one packet on an AMD Zen 3 at
#     AVX2 (docs/performance.md); 32 registers hold a pair.
#   WALK_EVENT_LANES: how many of a walk's lanes (of WIDTH x WALK_PACKETS) wait, their rays
#     ended or their cells to be solved, before the walk solves those cells and refills its free
#     lanes (src/kernels/pyramid_walk.hpp): fewer keeps more lanes busy, more spreads the solves
#     and refills over more lanes. 1 at width 1. The outcomes are the same for any.
#   HIGHWAY_TARGET: the Google Highway target of the same instructions (HWY_AVX2, ...; for scalar
#     code Highway's portable one, which it compiles as HWY_EMU128 or HWY_SCALAR): where the
#     Highway port of the tutorial's POM runs at this ISA (src/baselines/highway_port.cpp).
#   CPU_FEATURES: a ;-list of the CPU features code built with FLAGS needs, named as GCC's
#     __builtin_cpu_supports names them ("" for none); src/registry/isa.cpp checks them in C++.
#   FLAGS, AUTOVEC_FLAGS: ;-lists for the kernels, and added for the auto-vectorised naive port.
set(HEIGHTMARCH_ISA_IDS "")

function(heightmarch_isa id name header width march_packets walk_packets walk_event_lanes highway_target cpu_features
         flags)
  set(HEIGHTMARCH_ISA_IDS ${HEIGHTMARCH_ISA_IDS} ${id} PARENT_SCOPE)
  foreach(field name header width march_packets walk_packets walk_event_lanes highway_target cpu_features flags)
    set(HEIGHTMARCH_ISA_${id}_${field} "${${field}}" PARENT_SCOPE)
  endforeach()
  set(HEIGHTMARCH_ISA_${id}_autovec_flags "${ARGN}" PARENT_SCOPE)
endfunction()

# Every architecture: the scalar reference, which every other ISA is held to.
heightmarch_isa(scalar "scalar" vfloat1.hpp 1 1 1 1 "HWY_EMU128|HWY_SCALAR" "" "")
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  # GCC's generic tuning emulates gathers with scalar loads (2.5x slower measured on an AMD EPYC)
  # unless told to use the ISA's (-mtune-ctrl); it changes no result.
  set(gathers "$<$<CXX_COMPILER_ID:GNU>:-mtune-ctrl=use_gather_2parts,use_gather_4parts,use_gather>")
  heightmarch_isa(sse42 "sse4.2" vfloat4_sse.hpp 4 2 1 2 HWY_SSE4 "sse4.2" "-msse4.2")
  heightmarch_isa(avx2 "avx2" vfloat8_avx2.hpp 8 2 1 4 HWY_AVX2 "avx2;fma;bmi2" "-mavx2;-mfma;-mbmi2" ${gathers})
  # GCC 12's AVX-512 headers warn about their own _mm512_undefined_* values.
  heightmarch_isa(avx512 "avx512" vfloat16_avx512.hpp 16 2 2 16 HWY_AVX3
    "avx2;fma;bmi2;avx512f;avx512bw;avx512dq;avx512vl"
    "-mavx512f;-mavx512bw;-mavx512dq;-mavx512vl;-mfma;-mbmi2;-Wno-maybe-uninitialized;-Wno-uninitialized" ${gathers})
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64|ARM64)$")
  # Advanced SIMD is the AArch64 baseline: no CPU feature to check, no flag. Its packets are
  # SSE4.2's width with 32 registers, which hold a walk's pair as AVX-512's do.
  heightmarch_isa(neon "neon" vfloat4_neon.hpp 4 2 2 4 HWY_NEON "" "")
endif()

# Sets what a per-ISA template (src/isa/*.cpp.in, tests/*.cpp.in) is configured with for the ISA
# ID: ISA_ID, ISA_HEADER, ISA_WIDTH, ISA_MARCH_WIDTH, ISA_WALK_WIDTH, ISA_WALK_EVENT_LANES, ISA_PAIRED.
macro(heightmarch_isa_fields id)
  set(ISA_ID ${id})
  set(ISA_HEADER ${HEIGHTMARCH_ISA_${id}_header})
  set(ISA_WIDTH ${HEIGHTMARCH_ISA_${id}_width})
  math(EXPR ISA_MARCH_WIDTH "${ISA_WIDTH} * ${HEIGHTMARCH_ISA_${id}_march_packets}")
  math(EXPR ISA_WALK_WIDTH "${ISA_WIDTH} * ${HEIGHTMARCH_ISA_${id}_walk_packets}")
  set(ISA_WALK_EVENT_LANES ${HEIGHTMARCH_ISA_${id}_walk_event_lanes})
  if(HEIGHTMARCH_ISA_${id}_march_packets GREATER 1 OR HEIGHTMARCH_ISA_${id}_walk_packets GREATER 1)
    set(ISA_PAIRED 1)
  else()
    set(ISA_PAIRED 0)
  endif()
endmacro()

# Configures TEMPLATE once per ISA into OUT_DIR/NAME_<id>.cpp, each compiled with its ISA's flags;
# appends the units to the list variable SOURCES.
function(heightmarch_per_isa_units template out_dir name sources)
  set(units ${${sources}})
  foreach(id ${HEIGHTMARCH_ISA_IDS})
    heightmarch_isa_fields(${id})
    set(unit ${out_dir}/${name}_${id}.cpp)
    configure_file(${template} ${unit} @ONLY)
    set_source_files_properties(${unit} PROPERTIES COMPILE_OPTIONS "${HEIGHTMARCH_ISA_${id}_flags}")
    list(APPEND units ${unit})
  endforeach()
  set(${sources} ${units} PARENT_SCOPE)
endfunction()

# Writes the generated C++ list and the per-ISA translation units into OUT_DIR; sets
# HEIGHTMARCH_KERNEL_SOURCES to those units, each with its ISA's compile options.
function(heightmarch_generate_isas source_dir out_dir)
  set(rows "")
  set(highway_rows "")
  set(sources "")
  foreach(id ${HEIGHTMARCH_ISA_IDS})
    heightmarch_isa_fields(${id})
    string(REPLACE ";" " " features "${HEIGHTMARCH_ISA_${id}_cpu_features}")
    string(APPEND rows "  X(${id}, \"${HEIGHTMARCH_ISA_${id}_name}\", ${ISA_WIDTH}, ${ISA_MARCH_WIDTH}, ${ISA_WALK_WIDTH}, \"${features}\") \\\n")
    string(APPEND highway_rows "  X(${id}, (${HEIGHTMARCH_ISA_${id}_highway_target})) \\\n")
    foreach(kind kernels autovec)
      set(unit ${out_dir}/isa/${kind}_${id}.cpp)
      configure_file(${source_dir}/src/isa/${kind}.cpp.in ${unit} @ONLY)
      set(options ${HEIGHTMARCH_ISA_${id}_flags})
      if(kind STREQUAL "autovec")
        # `omp simd` without the OpenMP runtime; GCC 12 if-converts the port's loops only
        # without trapping math. Neither changes a result (contraction stays off).
        list(APPEND options -fopenmp-simd -fno-trapping-math ${HEIGHTMARCH_ISA_${id}_autovec_flags})
      endif()
      set_source_files_properties(${unit} PROPERTIES COMPILE_OPTIONS "${options}")
      list(APPEND sources ${unit})
    endforeach()
  endforeach()
  set(ISA_ROWS "${rows}")
  configure_file(${source_dir}/cmake/isa_list.hpp.in ${out_dir}/public/heightmarch/isa_list.hpp @ONLY)
  set(ISA_HIGHWAY_ROWS "${highway_rows}")
  configure_file(${source_dir}/cmake/highway_targets.hpp.in ${out_dir}/highway_targets.hpp @ONLY)
  set(HEIGHTMARCH_KERNEL_SOURCES ${sources} PARENT_SCOPE)
endfunction()
