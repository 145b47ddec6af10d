-- queue.sql — the lubdemd job queue (SQLite >= 3.37, STRICT tables). Embedded into the
-- lubdemd binary at build time and applied with CREATE ... IF NOT EXISTS on every start.
-- Connection pragmas (WAL, busy_timeout, synchronous=NORMAL, foreign_keys) are set in code
-- on every connection. Times are seconds since the Unix epoch (REAL, sub-second) computed
-- inside the transaction that writes them.

CREATE TABLE IF NOT EXISTS meta(
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
) STRICT;
INSERT OR IGNORE INTO meta(key, value) VALUES ('schema_version', '1');

CREATE TABLE IF NOT EXISTS users(
  id         INTEGER PRIMARY KEY,
  name       TEXT NOT NULL UNIQUE,
  is_admin   INTEGER NOT NULL DEFAULT 0 CHECK(is_admin IN (0, 1)),
  max_active INTEGER,                 -- per-user cap on accepted+running; NULL = server default
  created    REAL NOT NULL
) STRICT;

-- Bearer tokens "lub_<id>_<secret>": only sha256(secret) is stored; lookup by id.
CREATE TABLE IF NOT EXISTS tokens(
  id            TEXT PRIMARY KEY,
  user_id       INTEGER NOT NULL REFERENCES users(id),
  secret_sha256 TEXT NOT NULL,
  created       REAL NOT NULL,
  revoked       REAL
) STRICT;

CREATE TABLE IF NOT EXISTS jobs(
  seq            INTEGER PRIMARY KEY,   -- submission order (paging cursor, FIFO tie-break)
  id             TEXT NOT NULL UNIQUE,  -- random 128-bit hex, never sequential
  user_id        INTEGER NOT NULL REFERENCES users(id),
  process_id     TEXT NOT NULL,
  state          TEXT NOT NULL
                 CHECK(state IN ('accepted','running','successful','failed','dismissed')),
  priority       INTEGER NOT NULL DEFAULT 0 CHECK(priority BETWEEN -10 AND 10),
  request_json   TEXT NOT NULL,         -- POST body as received
  spec_json      TEXT NOT NULL,         -- engine spec: inputs + "scene"
  request_sha256 TEXT NOT NULL,         -- fingerprint of the canonical request
  created        REAL NOT NULL,
  started        REAL,
  finished       REAL,
  updated        REAL NOT NULL,
  progress       INTEGER NOT NULL DEFAULT 0 CHECK(progress BETWEEN 0 AND 100),
  message        TEXT,
  failure_kind   TEXT CHECK(failure_kind IN ('executor','system','cancelled')),
  attempt        INTEGER NOT NULL DEFAULT 0,
  max_attempts   INTEGER NOT NULL DEFAULT 3,
  worker         TEXT,
  lease_token    TEXT,                  -- fencing token of the current claim
  lease_until    REAL,
  heartbeat      REAL,
  engine_pid     INTEGER,
  purged         INTEGER NOT NULL DEFAULT 0,  -- finished job dismissed: files deleted, tombstone
  CHECK(lease_until IS NOT NULL OR state <> 'running')
) STRICT;
CREATE INDEX IF NOT EXISTS jobs_claim ON jobs(priority DESC, seq) WHERE state = 'accepted';
CREATE INDEX IF NOT EXISTS jobs_user ON jobs(user_id, seq);
CREATE INDEX IF NOT EXISTS jobs_lease ON jobs(lease_until) WHERE state = 'running';
CREATE INDEX IF NOT EXISTS jobs_active ON jobs(user_id) WHERE state IN ('accepted','running');

CREATE TABLE IF NOT EXISTS idempotency(
  user_id        INTEGER NOT NULL,
  key            TEXT NOT NULL,
  request_sha256 TEXT NOT NULL,
  job_id         TEXT NOT NULL,
  created        REAL NOT NULL,
  PRIMARY KEY(user_id, key)
) STRICT;
CREATE INDEX IF NOT EXISTS idempotency_created ON idempotency(created);

-- Files of a finished job: all of a successful one, what the engine of a failed one wrote
-- (registered in the same transaction that marks it successful or failed).
CREATE TABLE IF NOT EXISTS results(
  job_id     TEXT NOT NULL,
  name       TEXT NOT NULL,
  media_type TEXT NOT NULL,
  size       INTEGER NOT NULL,
  sha256     TEXT NOT NULL,
  PRIMARY KEY(job_id, name)
) STRICT;

-- Append-only audit of state transitions (submissions, claims, finishes, requeues, releases at
-- a service stop, dismissals, and purges: a DELETE of a job that had ended): lets tests prove
-- "final state reached exactly once" and "no overlapping attempts".
CREATE TABLE IF NOT EXISTS job_events(
  seq     INTEGER PRIMARY KEY,
  job_id  TEXT NOT NULL,
  at      REAL NOT NULL,
  event   TEXT NOT NULL,   -- submitted|claimed|successful|failed|dismissed|requeued|released|purged
  attempt INTEGER NOT NULL,
  worker  TEXT,
  token   TEXT
) STRICT;
CREATE INDEX IF NOT EXISTS job_events_job ON job_events(job_id, seq);
