/* file_copy.h — a whole-file copy, put on disk before it returns: what a periodic checkpoint
 * makes of the result.h5 being written (periodic_checkpoint.h); and the fsync of a file or
 * folder by name, before and after a rename into place.
 *
 * LUB_COPY_IN_KERNEL copies with copy_file_range(2): the file system may share the blocks (a
 * reflink on XFS or Btrfs, no data moved), copy on the server (NFS 4.2), or copy inside the
 * kernel (ext4), never through a user-space buffer; where the call is not available for the
 * two files (an old kernel, two file systems it cannot copy between) nothing has been copied
 * yet and the copy goes through a buffer instead. LUB_COPY_BUFFERED always uses the buffer
 * (read/write of 64 KiB), the way the copy was made before 2026-12-06; tests compare the two.
 *
 * Ownership: the paths are borrowed. dst is created (mode 0644 before the umask) or truncated,
 * written, fsync'ed and closed; it is not renamed (the caller publishes it). Errors: -1 with
 * errno set (the open, copy, fsync or close that failed); dst may then hold part of src.
 * Thread-safe (no state).
 */
#ifndef LUBDEM_FILE_COPY_H
#define LUBDEM_FILE_COPY_H

typedef enum { LUB_COPY_IN_KERNEL, LUB_COPY_BUFFERED } lub_copy_how;

/* src to dst, synced; 0, or -1 with errno set. *used (may be NULL) is set, on success, to the
 * way the bytes went: LUB_COPY_BUFFERED when `how` asked for it or the kernel could not copy
 * these files (the fall-back). */
int lub_file_copy(const char *src, const char *dst, lub_copy_how how, lub_copy_how *used);

/* Puts the file or folder `path` on disk (open, fsync, close): a file before it is renamed into
 * place, so that after a crash of the machine the name holds the whole file, not an empty or
 * partial one; a folder after a rename into it, so that the new name survives the crash too.
 * 0, or -1 with errno set (the open, fsync or close that failed). */
int lub_sync_path(const char *path);
/* lub_sync_path of the folder holding path ("." when path names no folder). */
int lub_sync_folder_of(const char *path);

#endif
