#!/usr/bin/env bash
# The fast test suite, twice: an optimised build with -Werror, then an ASan+UBSan build.
# Long physics validations (label "physics"), benchmarks ("bench") and the Slurm recipe
# ("slurm": needs root, slurm-wlm and munge) and the ThreadSanitizer check ("tsan") are not
# run here:
#   ctest --test-dir build -L physics   /   -L bench   /   -L slurm   /   -L tsan
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build -DLUBDEM_WERROR=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$jobs"
cmake -S . -B build-asan -DLUBDEM_WERROR=ON -DLUBDEM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build-asan -j"$jobs"
echo "== sanitizer build (ASan+UBSan) =="
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -LE "physics|bench|slurm|tsan|no_sanitizer" -j"$jobs"
echo "== optimised build =="
ctest --test-dir build --output-on-failure -LE "physics|bench|slurm|tsan" -j"$jobs"
