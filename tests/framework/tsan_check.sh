#!/usr/bin/env bash
# ThreadSanitizer check of the OpenMP engine (ctest label "tsan", not in tests/run_all.sh: it
# builds a third tree and takes about 6 minutes on 2 cores). gcc's libgomp is not instrumented,
# so TSan reports its barriers as races; this builds `lubdem` with clang and LLVM's libomp,
# whose Archer tool tells TSan about the runtime's synchronisation.
#   usage: tsan_check.sh SOURCE_DIR WORK_DIR
# 1. the control: a deliberate race (tests/framework/tsan_probe.c) must be reported and the
#    same program with only a barrier, an `omp for` and a reduction must not;
# 2. short runs of the parallel scenes on 2 threads (both controls of simple_shear, the
#    Delaunay set, microstructure, snapshots, the pair network, a cell flip, resuspension in
#    both orientations) must give no report. Prints tsan_reports_<run>=N lines.
# Needs clang and libomp-14-dev (.ci/install-deps installs both).
set -uo pipefail
src=$1
work=$2
omp_dir=/usr/lib/llvm-14/lib
for f in "$omp_dir/libomp.so" "$omp_dir/libarcher.so"; do
  if [ ! -e "$f" ]; then
    echo "error: $f is missing: install clang and libomp-14-dev (bash .ci/install-deps)" >&2
    exit 1
  fi
done
mkdir -p "$work"
fail=0
export TSAN_OPTIONS="halt_on_error=0 history_size=4 exitcode=0 ignore_noninstrumented_modules=1"
export ARCHER_OPTIONS="verbose=1"
reports() { cat "$1".* 2>/dev/null | grep -c 'WARNING: ThreadSanitizer'; }

# 1. the control
clang -O1 -g -fsanitize=thread -fopenmp=libomp -L"$omp_dir" -Wl,-rpath,"$omp_dir" \
  "$src/tests/framework/tsan_probe.c" -o "$work/tsan_probe" || exit 1
for mode in race clean; do
  rm -f "$work/probe_$mode".*
  TSAN_OPTIONS="$TSAN_OPTIONS log_path=$work/probe_$mode" "$work/tsan_probe" "$mode" \
    > "$work/probe_$mode.out" || fail=1
  n=$(reports "$work/probe_$mode")
  echo "tsan_reports_probe_$mode=$n"
  grep -q 'Archer detected OpenMP application with TSan' "$work/probe_$mode.out" ||
    { echo "FAIL: Archer is not active: TSan cannot see the OpenMP synchronisation" >&2; fail=1; }
  if [ "$mode" = race ] && [ "$n" -eq 0 ]; then echo "FAIL: the deliberate race was not reported" >&2; fail=1; fi
  if [ "$mode" = clean ] && [ "$n" -ne 0 ]; then echo "FAIL: a barrier or reduction was reported" >&2; fail=1; fi
done
[ $fail -eq 0 ] || exit 1

# 2. the engine, built with TSan and libomp (no LTO, no -Werror: clang's warnings differ)
CC=clang cmake -S "$src" -B "$work/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUBDEM_LTO=OFF \
  -DLUBDEM_WERROR=OFF -DCMAKE_C_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread -Wl,-rpath,$omp_dir" \
  -DOpenMP_C_FLAGS="-fopenmp=libomp" -DOpenMP_C_LIB_NAMES=omp \
  -DOpenMP_omp_LIBRARY="$omp_dir/libomp.so" > "$work/configure.log" 2>&1 ||
  { cat "$work/configure.log" >&2; exit 1; }
cmake --build "$work/build" --target lubdem -j"$(nproc)" > "$work/build.log" 2>&1 ||
  { tail -30 "$work/build.log" >&2; exit 1; }
lubdem=$work/build/engine/lubdem
run() { # NAME SPEC [lubdem run options]
  local name=$1 spec=$2
  shift 2
  rm -rf "$work/out_$name" "$work/tsan_$name".*
  echo "$spec" > "$work/$name.json"
  TSAN_OPTIONS="$TSAN_OPTIONS log_path=$work/tsan_$name" \
    "$lubdem" run "$work/$name.json" --out "$work/out_$name" --threads 2 --quiet "$@" \
    > "$work/$name.out" 2> "$work/$name.err"
  local rc=$? n
  n=$(reports "$work/tsan_$name")
  echo "tsan_reports_$name=$n"
  if [ $rc -ne 0 ] || [ "$n" -ne 0 ] || ! grep -q '"threads": 2' "$work/out_$name/summary.json"; then
    echo "FAIL: $name: exit $rc, $n reports (first lines below; $work/tsan_$name.*)" >&2
    cat "$work/tsan_$name".* 2>/dev/null | head -40 >&2
    fail=1
  fi
}
run volume_microstructure '{"scene":"simple_shear","n_particles":300,"strain":0.2,"microstructure":{"enabled":true,"start_strain":0,"interval_strain":0.002},"snapshots":4,"pair_network":"snapshots"}'
run pressure_flip '{"scene":"simple_shear","n_particles":300,"strain":0.65,"control":"pressure","Iv":0.05,"drag_viscosity":0.5,"snapshots":2,"pair_network":"final"}'
run delaunay '{"scene":"simple_shear","n_particles":300,"strain":0.15,"lubrication_pairs":"delaunay","delaunay_update_strain":0.002}'
run resuspension_gradient '{"scene":"resuspension","n":300,"strain":0.2,"average_from":0.1,"snapshots":3,"pair_network":"snapshots"}'
run resuspension_vorticity '{"scene":"resuspension","n":300,"strain":0.2,"average_from":0.1,"orientation":"vorticity"}'
exit $fail
