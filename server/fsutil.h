/* fsutil.h — small filesystem helpers for job directories.
 * All functions return 0 on success and -1 with errno set on failure; nothing is retained.
 * Buffers returned by lubd_read_file are malloc'd, NUL-terminated and owned by the caller. */
#ifndef LUBD_FSUTIL_H
#define LUBD_FSUTIL_H

#include <stddef.h>
#include <stdint.h>

int lubd_mkdir_p(const char *path, unsigned mode);
/* Removes a file or a directory tree (no symlink following). Missing path = success. */
int lubd_rm_rf(const char *path);
/* Called while a file is hashed, after every 16 MiB read; a non-zero return stops the hash. */
typedef int (*lubd_hash_tick)(void *ctx);
/* SHA-256 (hex) and size of a regular file. tick (may be NULL) lets a long hash keep a lease
 * alive; when it asks to stop, the call fails with errno ECANCELED. */
int lubd_file_sha256(const char *path, char hex[65], uint64_t *size, lubd_hash_tick tick,
                     void *tick_ctx);
/* Reads at most max bytes; fails with EFBIG if the file is larger. */
char *lubd_read_file(const char *path, size_t max, size_t *len);
/* Writes data to path via path.tmp + fsync + rename. */
int lubd_write_file_atomic(const char *path, const void *data, size_t n);
/* dst as a hard link to src, or, where the file system refuses one (another file system, no
 * hard links), as a copy (written to dst.tmp, then renamed). dst must not exist. */
int lubd_link_or_copy(const char *src, const char *dst);
/* snprintf for paths and messages: returns -1 (errno ENAMETOOLONG) if truncated. */
int lubd_pathf(char *buf, size_t n, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* n random bytes from /dev/urandom, hex encoded into out (2n+1 chars). */
int lubd_random_hex(char *out, size_t nbytes);

#endif
