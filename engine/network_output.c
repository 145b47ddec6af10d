/* network_output.c — /pair_network of result.h5 (see network_output.h). */
#include "network_output.h"

#include <stdio.h>
#include <string.h>

enum { LUB_NETWORK_COLUMNS = 14 };

int lub_spec_pair_network(json_t *obj, int *mode, lub_error *err)
{
    static const char *modes[] = {"none", "final", "snapshots", NULL};
    json_t *given = json_object_get(obj, "pair_network");
    if (json_is_boolean(given))
        json_object_set_new(obj, "pair_network",
                            json_string(json_is_true(given) ? "final" : "none"));
    const char *name = NULL;
    if (lub_spec_enum(obj, "", "pair_network", modes, "none", &name, err))
        return -1;
    *mode = strcmp(name, "snapshots") == 0 ? LUB_NETWORK_SNAPSHOTS
            : strcmp(name, "final") == 0   ? LUB_NETWORK_FINAL
                                           : LUB_NETWORK_NONE;
    return 0;
}

/* The columns of /pair_network, in the order lub_network_append writes them. */
static void network_columns(const char *force_unit, const char *torque_unit,
                            lub_h5_column cols[LUB_NETWORK_COLUMNS])
{
    const lub_h5_column c[LUB_NETWORK_COLUMNS] = {
        {"i", LUB_H5_I64, 1, "1"},
        {"j", LUB_H5_I64, 1, "1"},
        {"image", LUB_H5_I64, 3, "1"},
        {"branch", LUB_H5_F64, 3, "a"},
        {"centre_gap", LUB_H5_F64, 1, "a"},
        {"gap", LUB_H5_F64, 1, "a"},
        {"contact", LUB_H5_I8, 1, "1"},
        {"sliding", LUB_H5_I8, 1, "1"},
        {"force_normal_contact", LUB_H5_F64, 1, force_unit},
        {"force_normal_lubrication", LUB_H5_F64, 1, force_unit},
        {"force_tangential_contact", LUB_H5_F64, 3, force_unit},
        {"force_tangential_lubrication", LUB_H5_F64, 3, force_unit},
        {"torque_roll", LUB_H5_F64, 3, torque_unit},
        {"torque_twist", LUB_H5_F64, 3, torque_unit},
    };
    memcpy(cols, c, sizeof c);
}

lub_h5_frames *lub_network_define(lub_h5 *out, const char *force_unit, const char *torque_unit,
                                  const char *time_unit)
{
    lub_h5_column cols[LUB_NETWORK_COLUMNS];
    network_columns(force_unit, torque_unit, cols);
    return lub_h5_frames_define(out, "pair_network", LUB_NETWORK_COLUMNS, cols, time_unit);
}

int lub_network_append(lub_h5_frames *frames, const lub_pair_network *net, int64_t step,
                       double time)
{
    const void *const data[LUB_NETWORK_COLUMNS] = {
        net->i,          net->j,       net->image,       net->branch,      net->centre_gap,
        net->gap,        net->contact, net->sliding,     net->fn_contact,  net->fn_lub,
        net->fs_contact, net->fs_lub,  net->torque_roll, net->torque_twist};
    return lub_h5_frames_append(frames, step, time, (int64_t)net->n, data);
}

void lub_network_warn_skipped(const lub_h5_frames *frames, json_t *warnings)
{
    int64_t first = 0;
    char why[256] = "";
    const int64_t skipped = frames ? lub_h5_frames_skipped(frames, &first, why, sizeof why) : 0;
    if (skipped <= 0)
        return;
    char text[512];
    snprintf(text, sizeof text,
             "%lld frame%s of /pair_network from step %lld on %s not written: %s; the other "
             "outputs are not affected; ask for \"final\" only (or run with more room)",
             (long long)skipped, skipped == 1 ? "" : "s", (long long)first,
             skipped == 1 ? "was" : "were", why);
    json_array_append_new(warnings, json_string(text));
}
