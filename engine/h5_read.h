/* h5_read.h — what the two HDF5 readers (checkpoint_file.h, h5md_reader.h) share: opening an
 * existing file read-only with a message that says why not, and whether a path of links
 * exists in it.
 *
 * Units: none. Ownership: the caller closes the file (H5Fclose). Errors: a message in err[len]
 * prefixed with `what` ("checkpoint: cannot open x.h5: No such file or directory"); a failed
 * lookup counts as missing. HDF5's error printing is silenced and its exit handler not
 * installed (as lub_h5_create does: this may be the process's first HDF5 call).
 */
#ifndef LUBDEM_H5_READ_H
#define LUBDEM_H5_READ_H

#include <hdf5.h>
#include <stddef.h>

/* path opened read-only; H5I_INVALID_HID (negative) with err set when it is missing, not a
 * regular file, not HDF5 or unreadable. err may not be NULL. */
hid_t lub_h5_open_read(const char *path, const char *what, char *err, size_t len);

/* 1 if every link along path ("a/b/c", "/a/b") exists from loc, else 0. HDF5 1.10's H5Lexists
 * fails on a missing intermediate group, or on a dataset taken for one, so each prefix is
 * checked in turn. */
int lub_h5_path_exists(hid_t loc, const char *path);

#endif
