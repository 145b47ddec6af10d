/* periodic_checkpoint.c — checkpoints while a run goes on (periodic_checkpoint.h). */
#include "periodic_checkpoint.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "checkpoint_file.h"
#include "file_copy.h"
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
    if (!pc->failure[0]) { /* the first reason, cut to the buffer */
        const size_t n = strnlen(why, sizeof pc->failure - 1);
        memcpy(pc->failure, why, n);
        pc->failure[n] = '\0';
    }
    pc->next_at = lub_wall_seconds() + pc->every_s;
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
    if (lub_file_copy(pc->live_path, pc->copy_tmp, LUB_COPY_IN_KERNEL, NULL)) {
        snprintf(why, sizeof why, "cannot copy result.h5: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return -1;
    }
    return 0;
}

int lub_periodic_publish(lub_periodic_ckpt *pc)
{
    char why[600];
    if (pc->notes > 0 && lub_ckpt_set_notes(pc->ckpt_tmp, pc->notes, pc->note_names, pc->note_texts,
                                            why, sizeof why) != 0) {
        lub_periodic_failed(pc, why);
        return -1;
    }
    /* the checkpoint on disk before it replaces the last one (the copy of result.h5 was synced
     * by lub_file_copy): until 2026-12-07 it was only flushed to the kernel, so that a crash of
     * the machine could leave an empty or partial checkpoint.h5 where the last good one was */
    if (lub_sync_path(pc->ckpt_tmp) != 0) {
        snprintf(why, sizeof why, "cannot put the checkpoint on disk: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return -1;
    }
    if (rename(pc->copy_tmp, pc->copy_dst) != 0 || rename(pc->ckpt_tmp, pc->ckpt_dst) != 0) {
        snprintf(why, sizeof why, "cannot rename the checkpoint into place: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return -1;
    }
    pc->written++;
    /* the new names on disk too; the checkpoint is in place either way, so a failure here is
     * recorded and the run goes on */
    if (lub_sync_folder_of(pc->ckpt_dst) != 0) {
        snprintf(why, sizeof why, "cannot put the folder's new names on disk: %s", strerror(errno));
        lub_periodic_failed(pc, why);
        return 0;
    }
    pc->next_at = lub_wall_seconds() + pc->every_s;
    return 0;
}
