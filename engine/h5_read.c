/* h5_read.c — opening an HDF5 file to read it, and link lookups (h5_read.h). */
#include "h5_read.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

hid_t lub_h5_open_read(const char *path, const char *what, char *err, size_t len)
{
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    if (!path || !*path) {
        snprintf(err, len, "%s: no file name", what);
        return H5I_INVALID_HID;
    }
    struct stat st;
    if (stat(path, &st) != 0) {
        snprintf(err, len, "%s: cannot open %s: %s", what, path, strerror(errno));
        return H5I_INVALID_HID;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(err, len, "%s: cannot open %s: not a regular file", what, path);
        return H5I_INVALID_HID;
    }
    errno = 0;
    const htri_t is_h5 = H5Fis_hdf5(path);
    if (is_h5 <= 0) {
        const int e = errno;
        if (is_h5 < 0 && e)
            snprintf(err, len, "%s: cannot open %s: %s", what, path, strerror(e));
        else
            snprintf(err, len, "%s: %s is not an HDF5 file", what, path);
        return H5I_INVALID_HID;
    }
    errno = 0;
    const hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0) {
        const int e = errno;
        snprintf(err, len, "%s: cannot open %s: %s", what, path,
                 e ? strerror(e) : "HDF5 cannot read it (damaged or cut short?)");
        return H5I_INVALID_HID;
    }
    return file;
}

int lub_h5_path_exists(hid_t loc, const char *path)
{
    const size_t n = strlen(path);
    char *buf = malloc(n + 1);
    if (!buf)
        return 0;
    memcpy(buf, path, n + 1);
    int ok = 1;
    for (size_t i = 1; ok && i <= n; ++i) {
        if (i < n && path[i] != '/')
            continue;
        if (path[i - 1] == '/') /* "//" or a trailing '/' */
            continue;
        buf[i] = '\0';
        ok = H5Lexists(loc, buf, H5P_DEFAULT) > 0;
        buf[i] = path[i];
    }
    free(buf);
    return ok;
}
