/* periodic_checkpoint.c — checkpoints while a run goes on (periodic_checkpoint.h). */
#include "periodic_checkpoint.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "progress.h"

void lub_periodic_init(lub_periodic_ckpt *pc, double every_s, const char *live_path,
                       const char *copy_tmp, const char *copy_dst, const char *ckpt_tmp,
                       const char *ckpt_dst)
{
    memset(pc, 0, sizeof *pc);
    pc->every_s = every_s;
    pc->next_at = lub_wall_seconds() + every_s;
    pc->live_path = live_path;
    pc->copy_tmp = copy_tmp;
    pc->copy_dst = copy_dst;
    pc->ckpt_tmp = ckpt_tmp;
    pc->ckpt_dst = ckpt_dst;
}

int lub_periodic_due(lub_periodic_ckpt *pc, int64_t step)
{
    return (step & 63) == 0 && lub_wall_seconds() >= pc->next_at;
}

void lub_periodic_failed(lub_periodic_ckpt *pc, const char *why)
{
    unlink(pc->copy_tmp);
    unlink(pc->ckpt_tmp);
    if (!pc->failure[0])
        snprintf(pc->failure, sizeof pc->failure, "%s", why);
    pc->next_at = lub_wall_seconds() + pc->every_s;
}

/* src to dst (created or truncated), synced; 0 or -1 with errno set */
static int copy_file(const char *src, const char *dst)
{
    const int in = open(src, O_RDONLY | O_CLOEXEC);
    if (in < 0)
        return -1;
    const int out = open(dst, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    int err = out < 0 ? errno : 0;
    char buf[1 << 16];
    while (!err) {
        const ssize_t got = read(in, buf, sizeof buf);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            err = got < 0 ? errno : 0;
            break;
        }
        for (ssize_t done = 0; done < got && !err;) {
            const ssize_t put = write(out, buf + done, (size_t)(got - done));
            if (put >= 0)
                done += put;
            else if (errno != EINTR)
                err = errno;
        }
    }
    if (out >= 0 && !err && fsync(out) != 0)
        err = errno;
    if (out >= 0 && close(out) != 0 && !err)
        err = errno;
    close(in);
    errno = err;
    return err ? -1 : 0;
}

int lub_periodic_copy_output(lub_periodic_ckpt *pc, lub_h5 *out)
{
    char why[400];
    if (lub_h5_output_lost(out, why, sizeof why)) {
        char text[sizeof why + 32];
        snprintf(text, sizeof text, "result.h5 was given up (%s)", why);
        lub_periodic_failed(pc, text);
        return -1;
    }
    if (lub_h5_flush(out)) {
        snprintf(why, sizeof why, "cannot flush result.h5: %s", lub_h5_last_error(out));
        lub_periodic_failed(pc, why);
        return -1;
    }
    if (copy_file(pc->live_path, pc->copy_tmp)) {
        snprintf(why, sizeof why, "cannot copy result.h5: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return -1;
    }
    return 0;
}

int lub_periodic_publish(lub_periodic_ckpt *pc)
{
    if (rename(pc->copy_tmp, pc->copy_dst) != 0 || rename(pc->ckpt_tmp, pc->ckpt_dst) != 0) {
        char why[300];
        snprintf(why, sizeof why, "cannot rename the checkpoint into place: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return -1;
    }
    pc->written++;
    pc->next_at = lub_wall_seconds() + pc->every_s;
    return 0;
}
