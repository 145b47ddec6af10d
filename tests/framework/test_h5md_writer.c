/* Writes an H5MD file through h5md_writer.c with known values; check_h5md.py then verifies
 * the layout (H5MD 1.1), the hard links and every value. Usage: test_h5md_writer OUT.h5 */
#include <stdio.h>
#include <string.h>

#include "h5md_writer.h"

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    char err[256];
    lub_h5 *f = lub_h5_create(argv[1], err, sizeof err);
    if (!f) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    const char *names[3] = {"scalar", "vec", "group/tensor"};
    const int ncomp[3] = {1, 3, 9};
    const char *units[3] = {"a", "eta gd", NULL};
    char longest[LUB_H5_UNIT_MAX + 1];
    memset(longest, 'a', LUB_H5_UNIT_MAX);
    longest[LUB_H5_UNIT_MAX] = '\0';
    if (lub_h5_set_units(f, longest, NULL, NULL, NULL) != -1 ||
        !strstr(lub_h5_last_error(f), "unit this long")) {
        fprintf(stderr, "a unit of %d characters was accepted\n", LUB_H5_UNIT_MAX);
        return 1;
    }
    longest[LUB_H5_UNIT_MAX - 1] = '\0'; /* the longest one kept */
    if (lub_h5_set_units(f, "1/gd", longest, NULL, NULL) ||
        lub_h5_set_units(f, "1/gd", "a", "a*gd", "gd")) {
        fprintf(stderr, "set_units: %s\n", lub_h5_last_error(f));
        return 1;
    }
    lub_h5_table *t = lub_h5_table_create(f, 3, names, ncomp, units);
    if (!t)
        return 1;
    if (lub_h5_set_units(f, "s", "m", NULL, NULL) != -1) { /* too late: the table has its own */
        fprintf(stderr, "units were changed after a table was defined\n");
        return 1;
    }
    /* 2500 rows: crosses two in-memory buffer flushes and one partial buffer */
    for (int r = 0; r < 2500; ++r) {
        double row[13];
        row[0] = r;
        for (int k = 0; k < 3; ++k)
            row[1 + k] = r + 0.1 * k;
        for (int k = 0; k < 9; ++k)
            row[4 + k] = r * 10 + k;
        if (lub_h5_table_append(t, 10 * r, 0.5 * r, row))
            return 1;
    }
    double radius[4] = {1, 1.1, 0.9, 1};
    const char *boundary[3] = {"periodic", "periodic", "periodic"};
    if (lub_h5_particles_define(f, 4, radius, boundary))
        return 1;
    for (int fr = 0; fr < 3; ++fr) {
        double pos[12], vel[12], edges[9] = {10, 0, 0, fr, 10, 0, 0, 0, 10};
        for (int i = 0; i < 12; ++i) {
            pos[i] = fr * 100 + i;
            vel[i] = -i;
        }
        if (lub_h5_particles_snapshot(f, fr * 7, fr * 0.7, edges, pos, vel, NULL, NULL))
            return 1;
    }
    double prof[6] = {0, 1, 2, 3, 4, 5};
    int64_t dims[2] = {3, 2};
    if (lub_h5_write_array(f, "phi_profile", 2, dims, prof, "1"))
        return 1;
    if (lub_h5_write_parameters(f, "{\"scene\": \"x\"}", "{\"scene\": \"x\", \"d\": 1}",
                                "{\"length\": \"a\"}"))
        return 1;
    if (lub_h5_close(f, "complete"))
        return 1;
    printf("h5md_rows=2500\n");
    return 0;
}
