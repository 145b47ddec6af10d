#!/usr/bin/env bash
# ci_submit.sh — submit a job from CI, wait with a timeout, fail on a failed job, download the
# HDF5 result and verify its sha256.
#
#   ci_submit.sh PROCESS INPUTS_JSON [TIMEOUT_S] [OUT_FILE]
#   LUBDEM_URL, LUBDEM_TOKEN as in walkthrough.sh.
#   LUBDEM_IDEMPOTENCY_KEY  defaults to a key of the CI step and the request: the step as a
#                           retry keeps it (GitLab: $CI_PIPELINE_ID and $CI_JOB_NAME; GitHub
#                           Actions: $GITHUB_RUN_ID and $GITHUB_JOB), the request as a hash of
#                           PROCESS and INPUTS (so that one step may submit several), e.g.
#                           ci-gitlab-812-shear_sweep-simple_shear-3f0c1a9e5b7d2c44. Elsewhere
#                           the key is random, with a warning. A retried CI
#                           step gets the same job back instead of a duplicate, and waits for
#                           it (until 2026-12-07 the default used $CI_JOB_ID, which a GitLab
#                           retry changes, so a retry submitted a second job; and it left the
#                           inputs out, so a second submission of the step was refused, 409).
#                           A job this script timed out on is left running for that reason
#                           (exit 3 says how to dismiss it). Should the key's job have been
#                           dismissed (DELETE), the step submits anew under KEY-after-JOBID
#                           (KEY cut to 216 characters, so that the key stays within the
#                           service's 255; after a second dismissal KEY-after-JOBID2, not
#                           KEY-after-JOBID-after-JOBID2, which outgrew 255 for a long CI job
#                           name until 2026-12-07 and was refused, exit 2), a key that a
#                           further retry finds again.
#   LUBDEM_DISMISS_ON_TIMEOUT=1  dismiss the job on a timeout instead (a retried step then
#                           submits a new job, as above).
#   LUBDEM_FAIL_ON_WARNINGS=1  exit 4 when the run's summary has warnings (its own validity
#                           checks, e.g. simple_shear's elastic number); they are printed as
#                           'warning: ...' lines either way.
# A failed job whose engine wrote a summary leaves it in OUT_FILE.failed.json (the service's
# problem document, member "summary": the diagnostic, and the results of a run that completed
# but could not write its result.h5).
# Exit: 0 successful and verified, 1 job failed/dismissed/checksum mismatch, or the job could not
# be followed (the service unreachable, the token refused, the job deleted, a download failed),
# 2 rejected submission or the service unreachable when submitting (nothing submitted, as far as
# the script knows), 3 timeout, 4 successful and verified but with warnings
# (LUBDEM_FAIL_ON_WARNINGS=1). Each failure ends with an 'error: ...' line (until 2026-12-07 a
# failed curl ended the script with curl's own code: 7 for an unreachable service, 22 for an
# HTTP error while polling).
set -euo pipefail
PROCESS=${1:?process id}
INPUTS=${2:?inputs JSON object}
TIMEOUT=${3:-600}
OUT_FILE=${4:-result-$PROCESS.h5}
URL=${LUBDEM_URL:-http://127.0.0.1:8080}
TOKEN=${LUBDEM_TOKEN:?set LUBDEM_TOKEN}
# the CI step, as its retries see it (a job name may hold any character: kept to [A-Za-z0-9._-])
if [ -n "${CI_PIPELINE_ID:-}" ] && [ -n "${CI_JOB_NAME:-}" ]; then
  STEP="gitlab-$CI_PIPELINE_ID-$CI_JOB_NAME"
elif [ -n "${GITHUB_RUN_ID:-}" ] && [ -n "${GITHUB_JOB:-}" ]; then
  STEP="github-$GITHUB_RUN_ID-$GITHUB_JOB"
else
  STEP="random-$(od -An -N8 -tx1 /dev/urandom | tr -d ' \n')"
  [ -n "${LUBDEM_IDEMPOTENCY_KEY:-}" ] || echo "warning: neither LUBDEM_IDEMPOTENCY_KEY nor a CI" \
    "step (CI_PIPELINE_ID and CI_JOB_NAME, or GITHUB_RUN_ID and GITHUB_JOB) is set: a retry of" \
    "this step submits a second job" >&2
fi
STEP=$(printf '%s' "$STEP" | tr -c 'A-Za-z0-9._-' '_' | cut -c1-150)
REQUEST=$(printf '%s\n%s' "$PROCESS" "$INPUTS" | sha256sum | cut -c1-16)
KEY=${LUBDEM_IDEMPOTENCY_KEY:-ci-$STEP-$PROCESS-$REQUEST}
BASE_KEY=${KEY:0:216}  # + "-after-" + a job id (39 characters) <= 255
AUTH="Authorization: Bearer $TOKEN"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
field() { sed -n "s/^ *\"$1\": *\"\([^\"]*\)\".*/\1/p" | head -n 1; }
# get PATH OUT EXIT: GET $URL$PATH into OUT (curl's retries); on a failure an 'error:' line
# (the problem's detail for an HTTP error) and exit EXIT
get() {
  local code rc=0
  code=$(curl -sS --retry 5 --retry-all-errors -w '%{http_code}' -H "$AUTH" -o "$2" \
         "$URL$1") || rc=$?
  if [ "$rc" != 0 ]; then
    echo "error: GET $URL$1 failed (curl exit $rc): the service cannot be reached" >&2
    exit "$3"
  fi
  if [ "$code" != 200 ]; then
    echo "error: GET $URL$1: HTTP $code: $(field detail < "$2")" >&2
    exit "$3"
  fi
}

# A key names its request for a day: a job dismissed under it (by an earlier step's
# LUBDEM_DISMISS_ON_TIMEOUT=1, or by hand) would come back to every retry and fail it. Such a
# job is submitted again under KEY-after-JOBID, which the next retry finds in turn.
for TRY in 1 2 3 4 5 6; do
  RC=0
  CODE=$(curl -sS --retry 5 --retry-all-errors --retry-delay 1 -o "$TMP/job.json" -w '%{http_code}' \
         -H "$AUTH" -H 'Content-Type: application/json' -H "Idempotency-Key: $KEY" \
         -d "{\"inputs\": $INPUTS}" "$URL/processes/$PROCESS/execution") || RC=$?
  if [ "$RC" != 0 ]; then
    echo "error: POST $URL/processes/$PROCESS/execution failed (curl exit $RC): the service" \
         "cannot be reached; nothing was submitted, or a retry with Idempotency-Key $KEY finds" \
         "the job" >&2
    exit 2
  fi
  if [ "$CODE" != 201 ]; then
    echo "error: submission rejected (HTTP $CODE):"; cat "$TMP/job.json"; exit 2
  fi
  JOB=$(field jobID < "$TMP/job.json")
  [ "$(field status < "$TMP/job.json")" = dismissed ] || break
  if [ "$TRY" = 6 ]; then
    echo "job $JOB (Idempotency-Key $KEY) was dismissed, as were the jobs before it; giving up"
    exit 1
  fi
  echo "job $JOB (Idempotency-Key $KEY) was dismissed; submitting again"
  KEY="$BASE_KEY-after-$JOB"
done
echo "job $JOB submitted (Idempotency-Key $KEY)"
DEADLINE=$(( $(date +%s) + TIMEOUT ))
while :; do
  get "/jobs/$JOB" "$TMP/job.json" 1
  STATUS=$(field status < "$TMP/job.json")
  case "$STATUS" in successful|failed|dismissed) break ;; esac
  if [ "$(date +%s)" -ge "$DEADLINE" ]; then
    if [ "${LUBDEM_DISMISS_ON_TIMEOUT:-0}" = 1 ]; then
      echo "timeout after ${TIMEOUT}s (status $STATUS); dismissing job $JOB"
      curl -fsS -X DELETE -H "$AUTH" -o /dev/null "$URL/jobs/$JOB" || true
    else
      echo "timeout after ${TIMEOUT}s (status $STATUS): job $JOB is left to run, and a retried" \
           "step with Idempotency-Key $KEY waits for it; to cancel it:" \
           "curl -X DELETE -H 'Authorization: Bearer ...' $URL/jobs/$JOB"
    fi
    exit 3
  fi
  sleep 1
done
if [ "$STATUS" != successful ]; then
  MESSAGE=$(field message < "$TMP/job.json")
  echo "job $JOB $STATUS: ${MESSAGE#"$STATUS: "}"
  curl -fsS -H "$AUTH" "$URL/jobs/$JOB/log" | tail -n 20 || true
  # the failure's problem document carries the engine's summary where it wrote one (its
  # diagnostic; all results of a run that only lost its result.h5): keep it as an artifact
  if curl -sS -H "$AUTH" -o "$TMP/failed.json" "$URL/jobs/$JOB/results" \
     && grep -q '"summary"' "$TMP/failed.json"; then
    cp "$TMP/failed.json" "$OUT_FILE.failed.json"
    echo "the engine's summary of the failed run: $OUT_FILE.failed.json (member \"summary\")"
  fi
  exit 1
fi
get "/jobs/$JOB/results" "$TMP/results.json" 1
WANT=$(sed -n '/"outputs"/,$p' "$TMP/results.json" | sed -n '/"result.h5": {/,/}/p' | field sha256)
rm -f "$OUT_FILE"  # a fresh download; -C - makes curl's retries resume with a Range request
RC=0
curl -fsS --retry 5 --retry-all-errors -C - -H "$AUTH" -o "$OUT_FILE" \
     "$URL/jobs/$JOB/results/result.h5" || RC=$?
if [ "$RC" != 0 ]; then
  echo "error: download of $URL/jobs/$JOB/results/result.h5 failed (curl exit $RC)" >&2
  exit 1
fi
GOT=$(sha256sum "$OUT_FILE" | cut -d' ' -f1)
if [ -z "$WANT" ] || [ "$GOT" != "$WANT" ]; then
  echo "sha256 mismatch for $OUT_FILE: got $GOT, expected $WANT"; exit 1
fi
echo "job $JOB successful; $OUT_FILE sha256 $GOT verified"
# the summary's warnings (inline in the results document): one JSON array of strings without
# brackets or quotes inside them
WARNINGS=$(tr -d '\n' < "$TMP/results.json" | grep -o '"warnings": *\[[^]]*\]' | head -n 1 \
           | grep -o '"[^"]*"' | sed '1d; s/^"//; s/"$//' || true)
if [ -n "$WARNINGS" ]; then
  printf '%s\n' "$WARNINGS" | sed 's/^/warning: /'
  if [ "${LUBDEM_FAIL_ON_WARNINGS:-0}" = 1 ]; then
    echo "job $JOB has warnings (LUBDEM_FAIL_ON_WARNINGS=1)"; exit 4
  fi
fi
