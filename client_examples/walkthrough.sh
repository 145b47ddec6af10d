#!/usr/bin/env bash
# walkthrough.sh — a first round trip with curl: list processes, submit a falling_sphere job,
# poll it, fetch the summary, download the HDF5 result (resumable) and check its sha256.
#
#   LUBDEM_URL    service URL             [http://127.0.0.1:8080]
#   LUBDEM_TOKEN  bearer token            [contents of ./run/local-token]
#   LUBDEM_OUT    download directory      [./lubdem-download]
# Needs only bash, curl, sed, sha256sum.
set -euo pipefail
URL=${LUBDEM_URL:-http://127.0.0.1:8080}
TOKEN=${LUBDEM_TOKEN:-$(cat run/local-token)}
OUT=${LUBDEM_OUT:-./lubdem-download}
AUTH="Authorization: Bearer $TOKEN"
mkdir -p "$OUT"

# Extracts a top-level string member from a JSON document on stdin (no jq needed).
field() { sed -n "s/^ *\"$1\": *\"\([^\"]*\)\".*/\1/p" | head -n 1; }

echo "== processes"
curl -fsS "$URL/processes" | sed -n 's/^ *"id": *"\(.*\)",*/  \1/p'

echo "== submit falling_sphere (duration 2 tau_c)"
curl -fsS -D "$OUT/headers.txt" -o "$OUT/job.json" \
     -H "$AUTH" -H 'Content-Type: application/json' -H 'Prefer: respond-async' \
     -d '{"inputs": {"duration": 2.0, "u0": 1.0}}' \
     "$URL/processes/falling_sphere/execution"
JOB=$(field jobID < "$OUT/job.json")
echo "  job $JOB, $(grep -i '^location:' "$OUT/headers.txt" | tr -d '\r')"

echo "== poll"
for _ in $(seq 1 600); do
  curl -fsS -H "$AUTH" -o "$OUT/job.json" "$URL/jobs/$JOB"
  STATUS=$(field status < "$OUT/job.json")
  echo "  $STATUS: $(field message < "$OUT/job.json")"
  case "$STATUS" in successful|failed|dismissed) break ;; esac
  sleep 0.5
done
[ "$STATUS" = successful ] || { echo "job ended $STATUS"; exit 1; }

echo "== results (summary inline, file links with size and sha256)"
curl -fsS -H "$AUTH" -o "$OUT/results.json" "$URL/jobs/$JOB/results"
sed -n '/"outputs"/,$p' "$OUT/results.json" | head -n 20
WANT=$(sed -n '/"outputs"/,$p' "$OUT/results.json" | sed -n '/"result.h5": {/,/}/p' | field sha256)

echo "== download result.h5 (-C - resumes an interrupted download with a Range request)"
rm -f "$OUT/$JOB.h5"
curl -fsS -H "$AUTH" -C - -o "$OUT/$JOB.h5" "$URL/jobs/$JOB/results/result.h5"
GOT=$(sha256sum "$OUT/$JOB.h5" | cut -d' ' -f1)
[ "$GOT" = "$WANT" ] || { echo "sha256 mismatch: $GOT != $WANT"; exit 1; }
echo "  $OUT/$JOB.h5 sha256 $GOT OK"
echo "== engine log (last lines)"
curl -fsS -H "$AUTH" "$URL/jobs/$JOB/log" | tail -n 3
echo "read it with: python3 client_examples/read_result.py $OUT/$JOB.h5"
