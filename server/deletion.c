/* deletion.c — freeing the disk space of deleted jobs (see deletion.h). */
#include "deletion.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <unistd.h>

#include "continuation.h"
#include "fsutil.h"
#include "queue.h"
#include "sha256.h"
#include "status_json.h"

int lubd_deletion_free(sqlite3 *db, const char *jobs_dir, const char *id, char *why, size_t why_len)
{
    char dir[1200];
    if (lubd_pathf(dir, sizeof dir, "%s/%s", jobs_dir, id) != 0) {
        lubd_pathf(why, why_len, "path too long under %s", jobs_dir);
        return -1;
    }
    /* The service's request threads and its workers (other processes) may free one job at
     * once (a DELETE while the worker ends it): an exclusive lock on the folder makes the second
     * wait and then find it gone, instead of both handing over through the same temporary
     * folder and one removing what the other was linking. */
    const int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT)
            return 0;
        lubd_pathf(why, why_len, "could not open %s: %s", dir, strerror(errno));
        return -1;
    }
    /* where the file system cannot lock a folder opened for reading (NFS emulates flock with
     * write locks: EBADF), the free goes on unlocked, as before the lock existed: a rare race
     * on the hand-over then, never a folder that is not freed */
    while (flock(fd, LOCK_EX) != 0 && errno == EINTR)
        continue;
    int rc = 0;
    char reason[900] = "";
    if (access(dir, F_OK) != 0 && errno == ENOENT)
        rc = 0; /* freed by the holder of the lock while we waited */
    else if (lubd_continuation_hand_over(db, jobs_dir, id, reason, sizeof reason) < 0) {
        lubd_pathf(why, why_len, "%s; %s is kept", reason, dir);
        rc = 1;
    } else if (lubd_rm_rf(dir) != 0) {
        lubd_pathf(why, why_len, "could not delete %s: %s", dir, strerror(errno));
        rc = -1;
    }
    close(fd); /* releases the lock */
    return rc;
}

/* Removes jobs_dir/<id>/continued-from/: 1 removed, 0 not there, -1 not removable (*why). */
static int drop_handed_files(const char *jobs_dir, const char *id, char *why, size_t why_len)
{
    char handed[1300];
    lubd_pathf(handed, sizeof handed, "%s/%s/" LUBD_CONTINUED_FROM, jobs_dir, id);
    if (access(handed, F_OK) != 0)
        return 0;
    if (lubd_rm_rf(handed) != 0) {
        lubd_pathf(why, why_len, "could not delete %s: %s", handed, strerror(errno));
        return -1;
    }
    return 1;
}

int lubd_deletion_continuation_ended(sqlite3 *db, const char *jobs_dir, const char *id,
                                     const char *source_id, char *why, size_t why_len)
{
    if (drop_handed_files(jobs_dir, id, why, why_len) < 0)
        return -1;
    lubd_job source;
    if (!source_id[0] || lubd_queue_get(db, source_id, &source) != 1 || !source.purged)
        return 0;
    return lubd_deletion_free(db, jobs_dir, source_id, why, why_len) == 0 ? 0 : -1;
}

int lubd_deletion_tidy_ended(const char *jobs_dir, const lubd_job *j, char *why, size_t why_len)
{
    if (j->purged || !lubd_job_finished(j))
        return 0;
    const int dismissed = strcmp(j->state, "dismissed") == 0;
    int removed = 0;
    char dir[1300];
    for (int k = 0; k <= j->attempt; ++k) {
        if (k == j->attempt && !dismissed)
            continue;
        if (k == 0)
            lubd_pathf(dir, sizeof dir, "%s/%s/resume-out", jobs_dir, j->id);
        else
            lubd_pathf(dir, sizeof dir, "%s/%s/attempt-%d/out", jobs_dir, j->id, k);
        if (access(dir, F_OK) != 0)
            continue;
        if (lubd_rm_rf(dir) != 0) {
            lubd_pathf(why, why_len, "could not delete %s: %s", dir, strerror(errno));
            return -1;
        }
        ++removed;
    }
    return removed;
}

/* What the sweep does with the folder of job j: 1 freed something, 0 nothing to do, -1 could
 * not (*why says why). */
static int sweep_one(sqlite3 *db, const char *jobs_dir, const lubd_job *j, char *why,
                     size_t why_len)
{
    if (j->purged)
        return lubd_deletion_free(db, jobs_dir, j->id, why, why_len) == 0 ? 1 : -1;
    if (!lubd_job_finished(j))
        return 0;
    const int tidied = lubd_deletion_tidy_ended(jobs_dir, j, why, why_len);
    if (tidied < 0 || !j->continue_from[0])
        return tidied > 0 ? 1 : tidied;
    const int dropped = drop_handed_files(jobs_dir, j->id, why, why_len);
    return dropped < 0 ? -1 : (dropped > 0 || tidied > 0);
}

int lubd_deletion_sweep(sqlite3 *db, const char *jobs_dir, int quiet)
{
    DIR *d = opendir(jobs_dir);
    if (!d) {
        if (errno == ENOENT)
            return 0;
        fprintf(stderr, "lubdemd: cannot read %s: %s\n", jobs_dir, strerror(errno));
        return -1;
    }
    int freed = 0, failed = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!lubd_is_hex(e->d_name, 16)) /* not a job's folder */
            continue;
        lubd_job j;
        const int found = lubd_queue_get(db, e->d_name, &j);
        if (found < 0) {
            failed = 1;
            break;
        }
        if (found == 0)
            continue;
        char why[1400] = "";
        const int rc = sweep_one(db, jobs_dir, &j, why, sizeof why);
        if (rc < 0)
            fprintf(stderr, "lubdemd: deleted job's files: %s\n", why);
        else if (rc > 0) {
            ++freed;
            if (!quiet)
                fprintf(stderr, "lubdemd: freed what job %s left on disk (%s)\n", j.id,
                        j.purged ? "it was deleted" : "files it no longer needs");
        }
    }
    closedir(d);
    if (failed) {
        fprintf(stderr, "lubdemd: cannot read the job database to sweep %s\n", jobs_dir);
        return -1;
    }
    return freed;
}
