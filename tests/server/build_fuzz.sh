#!/bin/sh
# build_fuzz.sh OUT CLANG ARGS... — builds the libFuzzer target. If clang fails (e.g. on a new
# engine file it cannot compile), the build itself stays green and OUT becomes a stub that
# prints the compiler output and fails, so the server.fuzz test reports it.
out=$1
shift
log="$out.build.log"
if "$@" -o "$out" > "$log" 2>&1; then
  exit 0
fi
{
  echo '#!/bin/sh'
  echo "echo 'the clang libFuzzer build failed:'"
  echo "cat '$log'"
  echo 'exit 1'
} > "$out"
chmod +x "$out"
echo "warning: clang build of $out failed (see $log); server.fuzz will fail"
