/* h5_path.c — whether a path of links exists in an HDF5 file (h5_path.h). */
#include "h5_path.h"

#include <stdlib.h>
#include <string.h>

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
