/* h5_path.h — whether a path of links exists in an HDF5 file (shared by the readers of
 * checkpoint_file.h and h5md_reader.h).
 *
 * Units: none. Ownership: nothing is kept. Errors: none; a failed lookup counts as missing
 * (also out of memory for the path's copy). HDF5's error printing must be silenced by the
 * caller, as both readers do.
 */
#ifndef LUBDEM_H5_PATH_H
#define LUBDEM_H5_PATH_H

#include <hdf5.h>

/* 1 if every link along path ("a/b/c", "/a/b") exists from loc, else 0. HDF5 1.10's H5Lexists
 * fails on a missing intermediate group, or on a dataset taken for one, so each prefix is
 * checked in turn. */
int lub_h5_path_exists(hid_t loc, const char *path);

#endif
