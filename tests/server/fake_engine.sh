#!/bin/sh
# fake_engine.sh — stands in for `lubdem run SPEC --out DIR` to drive the worker's failure
# paths that the real engine cannot be made to hit on demand. The spec's "duration" picks:
#   3 -> numerical failure: summary.json with a diagnostic, exit 3
#   4 -> output error (a system failure), exit 4: result.h5 could not be written, summary.json
#        keeps the run's results (as lubdem does since 2026-12-05)
#   11 -> the engine prints its core-file limit and an assertion, then crashes (SIGSEGV)
#   7 -> exit 0 without writing any output
#   5 -> stopped (exit 5) with a partial summary, a result.h5, a checkpoint.h5 and a leftover
#        temporary file: the kept files must be served with the failure, the temporary one not
#   13 -> completes (exit 0) with a 1200 MiB result.h5 (sparse: cheap to write, as slow to
#        checksum as any, 7 s here): its checksumming outlasts a 2 s lease
#   20 -> runs until it is stopped, a result.h5 written at the start
#   22 -> completes at once (exit 0) with a small summary.json and result.h5
#   21 -> ignores SIGTERM and goes on writing its result.h5, its folder made again should it
#         be removed, until SIGKILL (an engine slow to stop, deleted meanwhile)
#   8 -> writes a periodic checkpoint (checkpoint.h5, checkpoint-result.h5) and a temporary
#        .result.h5.tmp, then is killed with SIGKILL (as by the OOM killer); run with --resume
#        (from that checkpoint) it completes (exit 0)
#   6 -> as 8, but killed again on every run, --resume or not
#   9 -> ignores SIGXCPU and spins until the hard CPU time limit's SIGKILL
#   23 -> writes a checkpoint, prints an error line and runs until it is stopped (exit 5);
#         run with --resume it crashes (SIGSEGV) without a word
#   25 -> writes a periodic checkpoint (checkpoint.h5, checkpoint-result.h5) and a temporary
#         .result.h5.tmp, then runs until it is stopped (a service killed meanwhile)
#   28 -> as 25, but its checkpoint-result.h5 is of 1200 MiB (sparse: cheap to write, as slow
#         to checksum as any, 7 s here)
#   29 -> as 28 with 120 MiB (for the sanitizer build, whose checksumming is ten times slower)
#   24 -> as 23, but writes a result.h5 too, and on SIGTERM a summary.json (status
#         "interrupted", its diagnostic saying --resume continues the run) as lubdem does;
#         run with --resume it crashes (SIGSEGV) without a word
#   26 -> completes (exit 0) with summary.json, result.h5 and 20 more files: more than the
#         service lists (16)
#   27 -> completes (exit 0) with summary.json and a result.h5 of mode 000 (unreadable unless
#         the service runs as root)
spec=$2 out=$4
mkdir -p "$out"
echo "progress fraction=0.5000 step=10 steps_per_s=1.0e+03 eta_s=1.0"
case $(tr -d ' \n' < "$spec") in
  *'"duration":3'[,}]*)
    printf '{"scene": "falling_sphere", "status": "failed", "diagnostic": "NaN in the gap at step 10, t = 0.5"}\n' > "$out/summary.json"
    echo "error: numerical failure" >&2; exit 3 ;;
  *'"duration":4'[,}]*)
    printf '{"scene": "falling_sphere", "status": "failed", "exit_code": 4, "results": {"rebound_height": {"value": 0.25, "stderr": null, "unit": "a"}}, "diagnostic": "cannot write result.h5 in %s: No space left on device (closing the file)"}\n' "$out" > "$out/summary.json"
    echo "error: cannot write result.h5 in $out: No space left on device (closing the file)" >&2; exit 4 ;;
  *'"duration":11'[,}]*)
    echo "fake engine: core file size limit $(ulimit -c)" >&2
    echo "lubdem: pair_network.c:88: fill: Assertion \`k < n' failed." >&2
    kill -SEGV $$ ;;
  *'"duration":13'[,}]*)
    printf '{"scene": "falling_sphere", "status": "complete"}\n' > "$out/summary.json"
    truncate -s 1200M "$out/result.h5"; exit 0 ;;
  *'"duration":20'[,}]*)
    printf 'rows of a long run\n' > "$out/result.h5"
    while :; do sleep 0.1; done ;;
  *'"duration":22'[,}]*)
    printf '{"scene": "falling_sphere", "status": "complete"}\n' > "$out/summary.json"
    printf 'rows of a short run\n' > "$out/result.h5"; exit 0 ;;
  *'"duration":26'[,}]*)
    printf '{"scene": "falling_sphere", "status": "complete"}\n' > "$out/summary.json"
    printf 'rows of a short run\n' > "$out/result.h5"
    for k in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
      echo "extra $k" > "$out/extra-$k.txt"
    done; exit 0 ;;
  *'"duration":27'[,}]*)
    printf '{"scene": "falling_sphere", "status": "complete"}\n' > "$out/summary.json"
    printf 'rows of a short run\n' > "$out/result.h5"
    chmod 000 "$out/result.h5"; exit 0 ;;
  *'"duration":21'[,}]*)
    trap 'echo "fake engine: SIGTERM ignored"' TERM
    while :; do mkdir -p "$out"; echo row >> "$out/result.h5"; sleep 0.1; done ;;
  *'"duration":8'[,}]*|*'"duration":6'[,}]*)
    case " $* " in
      *" --resume "*)
        if [ ! -f "$out/checkpoint.h5" ]; then
          echo "error: fake engine: --resume without a checkpoint" >&2; exit 2
        fi
        case $(tr -d ' \n' < "$spec") in
          *'"duration":8'[,}]*)
            printf '{"scene": "falling_sphere", "status": "complete"}\n' > "$out/summary.json"
            printf 'rows of a continued run\n' > "$out/result.h5"
            rm -f "$out/checkpoint-result.h5" "$out/.result.h5.tmp"; exit 0 ;;
        esac ;;
    esac
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    printf 'rows up to the checkpoint\n' > "$out/checkpoint-result.h5"
    printf 'half-written\n' > "$out/.result.h5.tmp"
    echo "fake engine: checkpoint written"
    kill -KILL $$ ;;
  *'"duration":23'[,}]*)
    case " $* " in
      *" --resume "*) kill -SEGV $$ ;;
    esac
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    echo "error: the first run's last word" >&2
    trap 'exit 5' TERM
    while :; do sleep 0.1; done ;;
  *'"duration":24'[,}]*)
    case " $* " in
      *" --resume "*) kill -SEGV $$ ;;
    esac
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    printf 'rows of the first run\n' > "$out/result.h5"
    echo "fake engine: the first run's files are written"
    trap 'printf "{\"scene\": \"falling_sphere\", \"status\": \"interrupted\", \"exit_code\": 5, \"diagnostic\": \"stopped by a signal (SIGTERM): lubdem run --resume continues the run\"}\n" > "$out/summary.json"; exit 5' TERM
    while :; do sleep 0.1; done ;;
  *'"duration":25'[,}]*)
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    printf 'rows up to the checkpoint\n' > "$out/checkpoint-result.h5"
    printf 'half-written\n' > "$out/.result.h5.tmp"
    echo "fake engine: checkpoint written"
    while :; do sleep 0.1; done ;;
  *'"duration":28'[,}]*|*'"duration":29'[,}]*)
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    case $(tr -d ' \n' < "$spec") in
      *'"duration":28'[,}]*) truncate -s 1200M "$out/checkpoint-result.h5" ;;
      *) truncate -s 120M "$out/checkpoint-result.h5" ;;
    esac
    echo "fake engine: checkpoint written"
    while :; do sleep 0.1; done ;;
  *'"duration":9'[,}]*)
    trap '' XCPU
    while :; do :; done ;;
  *'"duration":7'[,}]*)
    exit 0 ;;
  *'"duration":5'[,}]*)
    printf '{"scene": "falling_sphere", "status": "partial", "exit_code": 5, "diagnostic": "stopped at the CPU time limit of this process"}\n' > "$out/summary.json"
    printf 'partial rows of the fake engine\n' > "$out/result.h5"
    printf 'state of the fake engine\n' > "$out/checkpoint.h5"
    printf 'half-written\n' > "$out/.result.h5.tmp"
    echo "error: stopped at the CPU time limit of this process" >&2; exit 5 ;;
esac
echo "error: fake engine: unexpected spec" >&2
exit 1
