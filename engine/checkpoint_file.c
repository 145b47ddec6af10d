/* checkpoint_file.c — typed store of named arrays in an HDF5 file (layout in checkpoint_file.h). */
#include "checkpoint_file.h"

#include "h5_read.h"

#include <errno.h>
#include <hdf5.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "h5md_writer.h" /* lub_h5_output_failure */

#define FORMAT_ATTR "lubdem_checkpoint"
#define CHECKSUMS_ATTR "lubdem_checksums" /* root: every dataset carries CRC_ATTR */
#define CRC_ATTR "crc32"                  /* a dataset's: the CRC-32 of its data */

struct lub_ckpt {
    hid_t file;
    int writable;      /* opened by lub_ckpt_create */
    int failed;        /* a put failed: the checkpoint is void, close returns -1 */
    int checksummed;   /* opened: the file says every dataset carries its CRC-32 */
    char *path;        /* for messages */
    char err[512];     /* the last error */
    char failure[512]; /* the first failed put's message */
};

/* An element type: file type (little-endian), memory type (native), and what identifies it in
 * a file (class, size, signedness). */
typedef struct {
    hid_t file, mem;
    size_t size;
    int is_float, is_signed;
    const char *label;
} elem_type;

static int elem_type_of(lub_ckpt_type t, elem_type *e)
{
    switch (t) {
    case LUB_CKPT_F64:
        *e = (elem_type){H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, 1, 1, "float64"};
        return 0;
    case LUB_CKPT_I64:
        *e = (elem_type){H5T_STD_I64LE, H5T_NATIVE_INT64, 8, 0, 1, "int64"};
        return 0;
    case LUB_CKPT_I32:
        *e = (elem_type){H5T_STD_I32LE, H5T_NATIVE_INT32, 4, 0, 1, "int32"};
        return 0;
    case LUB_CKPT_U8: *e = (elem_type){H5T_STD_U8LE, H5T_NATIVE_UINT8, 1, 0, 0, "uint8"}; return 0;
    }
    return -1;
}

/* CRC-32 (the IEEE 802.3 polynomial, reflected: 0xEDB88320; zlib's crc32), eight bytes at a
 * time ("slicing by 8": t[k][b] is the CRC of byte b followed by k zero bytes). The tables are
 * made on each call (2048 entries, microseconds; no shared state), which takes ~0.1 s for 200 MB
 * of data. */
typedef struct {
    uint32_t t[8][256];
    uint32_t crc;
} crc32_state;

static void crc32_begin(crc32_state *st)
{
    for (uint32_t i = 0; i < 256; ++i) {
        uint32_t c = i;
        for (int k = 0; k < 8; ++k)
            c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
        st->t[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; ++i)
        for (int k = 1; k < 8; ++k)
            st->t[k][i] = (st->t[k - 1][i] >> 8) ^ st->t[0][st->t[k - 1][i] & 255u];
    st->crc = 0xFFFFFFFFu;
}

static void crc32_byte(crc32_state *st, unsigned char b)
{
    st->crc = (st->crc >> 8) ^ st->t[0][(st->crc ^ b) & 255u];
}

/* n bytes in their order */
static void crc32_bytes(crc32_state *st, const unsigned char *p, size_t n)
{
    uint32_t c = st->crc;
    for (; n >= 8; n -= 8, p += 8) {
        const uint32_t lo = c ^ ((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                                 (uint32_t)p[3] << 24);
        c = st->t[7][lo & 255u] ^ st->t[6][(lo >> 8) & 255u] ^ st->t[5][(lo >> 16) & 255u] ^
            st->t[4][lo >> 24] ^ st->t[3][p[4]] ^ st->t[2][p[5]] ^ st->t[1][p[6]] ^ st->t[0][p[7]];
    }
    st->crc = c;
    while (n--)
        crc32_byte(st, *p++);
}

/* The CRC-32 of count elements of size bytes at data, each taken in little-endian byte order
 * (the file's), so that a checkpoint checks the same on hosts of either byte order. */
static uint32_t crc32_elements(const void *data, size_t count, size_t size)
{
    const uint16_t one = 1;
    const int little = *(const unsigned char *)&one == 1;
    const unsigned char *p = data;
    crc32_state st;
    crc32_begin(&st);
    if (little || size == 1) {
        if (count > 0)
            crc32_bytes(&st, p, count * size);
    } else {
        for (size_t e = 0; e < count; ++e, p += size)
            for (size_t b = 0; b < size; ++b)
                crc32_byte(&st, p[size - 1 - b]);
    }
    return st.crc ^ 0xFFFFFFFFu;
}

/* What a dataset's file type holds, for messages ("int32", "float32", "text", ...). */
static void describe_type(hid_t t, char *buf, size_t len)
{
    const size_t bits = 8 * H5Tget_size(t);
    switch (H5Tget_class(t)) {
    case H5T_FLOAT: snprintf(buf, len, "float%zu", bits); break;
    case H5T_INTEGER:
        snprintf(buf, len, "%sint%zu", H5Tget_sign(t) == H5T_SGN_NONE ? "u" : "", bits);
        break;
    case H5T_STRING: snprintf(buf, len, "text"); break;
    default: snprintf(buf, len, "another type (HDF5 class %d)", (int)H5Tget_class(t)); break;
    }
}

static herr_t innermost_error(unsigned n, const H5E_error2_t *e, void *data)
{
    if (n == 0 && e->desc)
        snprintf((char *)data, 160, "%s", e->desc);
    return 0;
}

/* Why the HDF5 call that just failed failed: the system's reason when errno (e, saved right
 * after the call) is an output failure a user can act on, else the innermost message of HDF5's
 * error stack. Call before any other HDF5 call (the next one clears the stack). */
static void failure_reason(int e, char *buf)
{
    buf[0] = '\0';
    if (lub_h5_output_failure(e)) {
        snprintf(buf, 160, "%s", strerror(e));
        return;
    }
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost_error, buf);
    if (!buf[0])
        snprintf(buf, 160, "HDF5 error");
}

/* Message "checkpoint: /<name> <what>" in c->err; returns -1. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static int
fail(lub_ckpt *c, const char *name, const char *fmt, ...)
{
    char what[360];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (!name || !*name)
        snprintf(c->err, sizeof c->err, "checkpoint: (no dataset name) %s", what);
    else
        snprintf(c->err, sizeof c->err, "checkpoint: %s%.120s %s", name[0] == '/' ? "" : "/", name,
                 what);
    return -1;
}

/* A failed put voids the checkpoint (close returns -1 with the first failure's message). */
static int put_failed(lub_ckpt *c)
{
    if (!c->failed) {
        c->failed = 1;
        snprintf(c->failure, sizeof c->failure, "%s", c->err);
    }
    return -1;
}

static lub_ckpt *new_ckpt(const char *path)
{
    /* As in lub_h5_create: no HDF5 exit handler (a failed close left a file in HDF5's table
     * that the handler's second close crashed on); it must precede the process's first HDF5
     * call and is a no-op afterwards. We report errors ourselves. */
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    lub_ckpt *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->file = H5I_INVALID_HID;
    c->path = strdup(path);
    if (!c->path) {
        free(c);
        return NULL;
    }
    return c;
}

static void free_ckpt(lub_ckpt *c)
{
    free(c->path);
    free(c);
}

lub_ckpt *lub_ckpt_create(const char *path, char *err, size_t len)
{
    if (err && len > 0)
        err[0] = '\0';
    if (!path || !*path) {
        if (err && len > 0)
            snprintf(err, len, "checkpoint: no file name");
        return NULL;
    }
    lub_ckpt *c = new_ckpt(path);
    if (!c) {
        if (err && len > 0)
            snprintf(err, len, "checkpoint: out of memory creating %s", path);
        return NULL;
    }
    errno = 0;
    c->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (c->file < 0) {
        const int e = errno;
        char reason[160];
        failure_reason(e, reason);
        if (err && len > 0)
            snprintf(err, len, "checkpoint: cannot create %s: %s", path, e ? strerror(e) : reason);
        free_ckpt(c);
        return NULL;
    }
    c->writable = 1;
    return c;
}

/* The format version in the root attribute: 0, or -1 with err set. */
static int read_format(hid_t file, const char *path, long long *version, char *err, size_t len)
{
    if (H5Aexists(file, FORMAT_ATTR) <= 0) {
        snprintf(err, len,
                 "checkpoint: %s is not a lubdem checkpoint (no root attribute \"%s\": another "
                 "HDF5 file, or a checkpoint whose writing did not finish)",
                 path, FORMAT_ATTR);
        return -1;
    }
    hid_t a = H5Aopen(file, FORMAT_ATTR, H5P_DEFAULT);
    hid_t t = a >= 0 ? H5Aget_type(a) : H5I_INVALID_HID;
    hid_t s = a >= 0 ? H5Aget_space(a) : H5I_INVALID_HID;
    int64_t v = 0;
    const int ok = t >= 0 && s >= 0 && H5Tget_class(t) == H5T_INTEGER &&
                   H5Sget_simple_extent_npoints(s) == 1 && H5Aread(a, H5T_NATIVE_INT64, &v) >= 0;
    if (s >= 0)
        H5Sclose(s);
    if (t >= 0)
        H5Tclose(t);
    if (a >= 0)
        H5Aclose(a);
    if (!ok) {
        snprintf(err, len,
                 "checkpoint: %s is not a lubdem checkpoint (its attribute \"%s\" is not one "
                 "integer)",
                 path, FORMAT_ATTR);
        return -1;
    }
    *version = (long long)v;
    return 0;
}

lub_ckpt *lub_ckpt_open(const char *path, char *err, size_t len)
{
    char dummy[8];
    if (!err || len == 0) {
        err = dummy;
        len = sizeof dummy;
    }
    err[0] = '\0';
    if (!path || !*path) {
        snprintf(err, len, "checkpoint: no file name");
        return NULL;
    }
    lub_ckpt *c = new_ckpt(path);
    if (!c) {
        snprintf(err, len, "checkpoint: out of memory opening %s", path);
        return NULL;
    }
    c->file = lub_h5_open_read(path, "checkpoint", err, len);
    if (c->file < 0) {
        free_ckpt(c);
        return NULL;
    }
    long long version = 0;
    if (read_format(c->file, path, &version, err, len) < 0) {
        H5Fclose(c->file);
        free_ckpt(c);
        return NULL;
    }
    if (version != LUB_CKPT_FORMAT) {
        snprintf(err, len,
                 "checkpoint: %s has checkpoint format version %lld; this lubdem reads version "
                 "%d",
                 path, version, LUB_CKPT_FORMAT);
        H5Fclose(c->file);
        free_ckpt(c);
        return NULL;
    }
    c->checksummed = H5Aexists(c->file, CHECKSUMS_ATTR) > 0;
    return c;
}

const char *lub_ckpt_error(const lub_ckpt *c) { return c ? c->err : "checkpoint: no file"; }

/* Checks that a put may go ahead: 0, or -1 (the checkpoint void) with the message set. */
static int put_begin(lub_ckpt *c, const char *name)
{
    if (!c->writable)
        return fail(c, name, "not written: %s is open read-only", c->path);
    if (c->failed)
        return fail(c, name, "not written after an earlier failure (%.300s)", c->failure);
    if (!name || !*name) {
        fail(c, name, "not written: no name");
        return put_failed(c);
    }
    if (lub_h5_path_exists(c->file, name)) {
        fail(c, name, "exists already");
        return put_failed(c);
    }
    return 0;
}

/* Creates dataset name of file type ftype and space sp (intermediate groups created); writes
 * data (memory type mtype) unless data is NULL. 0, or -1 (the checkpoint void) with the message
 * naming the dataset and the reason. what: the content, for the message. */
/* Attribute `name` of object obj: one value of file type ftype, read from *value as mtype; 0 or
 * -1 (HDF5's error stack as it leaves it). */
static int write_scalar_attr(hid_t obj, const char *name, hid_t ftype, hid_t mtype,
                             const void *value)
{
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(obj, name, ftype, sp, H5P_DEFAULT, H5P_DEFAULT);
    const herr_t rc = a < 0 ? -1 : H5Awrite(a, mtype, value);
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    return rc < 0 ? -1 : 0;
}

static int put_dataset(lub_ckpt *c, const char *name, hid_t ftype, hid_t mtype, hid_t sp,
                       const void *data, const char *what, uint32_t crc)
{
    char reason[160];
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    errno = 0;
    hid_t d = H5Dcreate2(c->file, name, ftype, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    int rc = 0;
    if (d < 0) {
        failure_reason(errno, reason);
        rc = fail(c, name, "cannot be created (%s): %s", what, reason);
    } else if (data) {
        errno = 0;
        if (H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
            failure_reason(errno, reason);
            rc = fail(c, name, "cannot be written (%s): %s", what, reason);
        }
    }
    if (d >= 0 && rc == 0) { /* the data's CRC-32, which lub_ckpt_get checks */
        errno = 0;
        if (write_scalar_attr(d, CRC_ATTR, H5T_STD_U32LE, H5T_NATIVE_UINT32, &crc)) {
            failure_reason(errno, reason);
            rc = fail(c, name, "cannot be written (its CRC-32): %s", reason);
        }
    }
    if (d >= 0)
        H5Dclose(d);
    H5Pclose(lcpl);
    return rc < 0 ? put_failed(c) : 0;
}

int lub_ckpt_put(lub_ckpt *c, const char *name, lub_ckpt_type type, size_t count, const void *data)
{
    if (!c)
        return -1;
    if (put_begin(c, name) < 0)
        return -1;
    elem_type et;
    if (elem_type_of(type, &et) < 0) {
        fail(c, name, "not written: unknown element type %d", (int)type);
        return put_failed(c);
    }
    if (count > 0 && !data) {
        fail(c, name, "not written: no data for %zu elements", count);
        return put_failed(c);
    }
    const hsize_t dim = (hsize_t)count;
    hid_t sp = H5Screate_simple(1, &dim, NULL);
    if (sp < 0) {
        fail(c, name, "not written: no dataspace of %zu elements", count);
        return put_failed(c);
    }
    char what[64];
    snprintf(what, sizeof what, "%zu %s", count, et.label);
    /* count 0: nothing to write (HDF5 takes no empty write from a NULL buffer) */
    const int rc = put_dataset(c, name, et.file, et.mem, sp, count > 0 ? data : NULL, what,
                               crc32_elements(data, count, et.size));
    H5Sclose(sp);
    return rc;
}

int lub_ckpt_put_f64(lub_ckpt *c, const char *name, double v)
{
    return lub_ckpt_put(c, name, LUB_CKPT_F64, 1, &v);
}

int lub_ckpt_put_i64(lub_ckpt *c, const char *name, int64_t v)
{
    return lub_ckpt_put(c, name, LUB_CKPT_I64, 1, &v);
}

static hid_t text_type(H5T_cset_t cset)
{
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, cset);
    return t;
}

int lub_ckpt_put_text(lub_ckpt *c, const char *name, const char *text)
{
    if (!c)
        return -1;
    if (put_begin(c, name) < 0)
        return -1;
    if (!text) {
        fail(c, name, "not written: no text");
        return put_failed(c);
    }
    hid_t t = text_type(H5T_CSET_UTF8);
    hid_t sp = H5Screate(H5S_SCALAR);
    char what[64];
    snprintf(what, sizeof what, "text of %zu bytes", strlen(text));
    const int rc =
        put_dataset(c, name, t, t, sp, &text, what, crc32_elements(text, strlen(text), 1));
    H5Sclose(sp);
    H5Tclose(t);
    return rc;
}

/* Opens dataset name for reading: its id, or < 0 with the message set. */
static hid_t open_dataset(lub_ckpt *c, const char *name)
{
    if (!name || !*name) {
        fail(c, name, "cannot be read: no name");
        return H5I_INVALID_HID;
    }
    if (!lub_h5_path_exists(c->file, name)) {
        fail(c, name, "is missing from %s", c->path);
        return H5I_INVALID_HID;
    }
    hid_t d = H5Dopen2(c->file, name, H5P_DEFAULT);
    if (d < 0)
        fail(c, name, "is not a dataset");
    return d;
}

/* Elements of dataset d (of rank 0 or 1 when one_d): 0, or -1 with the message set. */
static int element_count(lub_ckpt *c, const char *name, hid_t d, int one_d, size_t *count)
{
    hid_t sp = H5Dget_space(d);
    const int rank = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
    const hssize_t n = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    if (sp >= 0)
        H5Sclose(sp);
    if (rank < 0 || n < 0)
        return fail(c, name, "has no readable shape");
    if (one_d && rank > 1)
        return fail(c, name, "is not a 1-D array (rank %d)", rank);
    *count = (size_t)n;
    return 0;
}

/* Checks the data just read from dataset d against the CRC-32 stored with it (crc: the data's):
 * 0, or -1 with the message naming the dataset. A dataset without one passes in a checkpoint
 * written before checksums were (2026-12-07), not in a later one. */
static int verify_crc(lub_ckpt *c, const char *name, hid_t d, uint32_t crc)
{
    const htri_t has = H5Aexists(d, CRC_ATTR);
    if (has == 0 && !c->checksummed)
        return 0;
    if (has <= 0)
        return fail(c, name, "is damaged: it has no CRC-32, which every dataset of %s has",
                    c->path);
    uint32_t stored = 0;
    hid_t a = H5Aopen(d, CRC_ATTR, H5P_DEFAULT);
    const int read = a >= 0 && H5Aread(a, H5T_NATIVE_UINT32, &stored) >= 0;
    if (a >= 0)
        H5Aclose(a);
    if (!read)
        return fail(c, name, "is damaged: its CRC-32 cannot be read");
    if (stored != crc)
        return fail(c, name,
                    "is damaged: its data's CRC-32 is %08x, the checkpoint recorded %08x when it "
                    "was written (a changed byte in %s)",
                    (unsigned)crc, (unsigned)stored, c->path);
    return 0;
}

int lub_ckpt_get_i64_or(lub_ckpt *c, const char *name, int64_t absent, int64_t *v)
{
    if (c && name && *name && lub_h5_path_exists(c->file, name) > 0)
        return lub_ckpt_get_i64(c, name, v);
    *v = absent;
    return 0;
}

int lub_ckpt_has(lub_ckpt *c, const char *name)
{
    return c && name && *name && lub_h5_path_exists(c->file, name) > 0;
}

int lub_ckpt_count(lub_ckpt *c, const char *name, size_t *count)
{
    if (!c)
        return -1;
    hid_t d = open_dataset(c, name);
    if (d < 0)
        return -1;
    size_t n = 0;
    const int rc = element_count(c, name, d, 0, &n);
    H5Dclose(d);
    if (rc == 0 && count)
        *count = n;
    return rc;
}

int lub_ckpt_get(lub_ckpt *c, const char *name, lub_ckpt_type type, size_t count, void *data)
{
    if (!c)
        return -1;
    elem_type et;
    if (elem_type_of(type, &et) < 0)
        return fail(c, name, "cannot be read: unknown element type %d", (int)type);
    hid_t d = open_dataset(c, name);
    if (d < 0)
        return -1;
    int rc = 0;
    hid_t ft = H5Dget_type(d);
    const H5T_class_t cls = ft >= 0 ? H5Tget_class(ft) : H5T_NO_CLASS;
    const int same = ft >= 0 && cls == (et.is_float ? H5T_FLOAT : H5T_INTEGER) &&
                     H5Tget_size(ft) == et.size &&
                     (et.is_float || (H5Tget_sign(ft) != H5T_SGN_NONE) == et.is_signed);
    if (!same) {
        char held[64] = "an unreadable type";
        if (ft >= 0)
            describe_type(ft, held, sizeof held);
        rc = fail(c, name, "holds %s, expected %s", held, et.label);
    }
    if (ft >= 0)
        H5Tclose(ft);
    size_t n = 0;
    if (rc == 0)
        rc = element_count(c, name, d, 1, &n);
    if (rc == 0 && n != count)
        rc = fail(c, name, "has %zu element%s, expected %zu", n, n == 1 ? "" : "s", count);
    if (rc == 0 && count > 0) {
        if (!data) {
            rc = fail(c, name, "cannot be read: no array to read %zu elements into", count);
        } else if ((errno = 0, H5Dread(d, et.mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)) {
            char reason[160];
            failure_reason(errno, reason);
            rc = fail(c, name, "cannot be read (%zu %s): %s", count, et.label, reason);
        }
    }
    if (rc == 0)
        rc = verify_crc(c, name, d, crc32_elements(data, count, et.size));
    H5Dclose(d);
    return rc;
}

int lub_ckpt_get_f64(lub_ckpt *c, const char *name, double *v)
{
    return lub_ckpt_get(c, name, LUB_CKPT_F64, 1, v);
}

int lub_ckpt_get_i64(lub_ckpt *c, const char *name, int64_t *v)
{
    return lub_ckpt_get(c, name, LUB_CKPT_I64, 1, v);
}

char *lub_ckpt_get_text(lub_ckpt *c, const char *name)
{
    if (!c)
        return NULL;
    hid_t d = open_dataset(c, name);
    if (d < 0)
        return NULL;
    char *out = NULL;
    hid_t ft = H5Dget_type(d);
    size_t n = 0;
    if (ft < 0 || H5Tget_class(ft) != H5T_STRING) {
        char held[64] = "an unreadable type";
        if (ft >= 0)
            describe_type(ft, held, sizeof held);
        fail(c, name, "holds %s, expected text", held);
    } else if (element_count(c, name, d, 1, &n) == 0 && n != 1) {
        fail(c, name, "has %zu texts, expected 1", n);
    } else if (n == 1 && H5Tis_variable_str(ft) > 0) {
        hid_t mt = text_type(H5Tget_cset(ft));
        char *s = NULL;
        if (H5Dread(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, &s) < 0) {
            fail(c, name, "cannot be read (text)");
        } else {
            const size_t len = s ? strlen(s) : 0;
            out = malloc(len + 1);
            if (!out)
                fail(c, name, "cannot be read: out of memory for %zu bytes of text", len);
            else {
                memcpy(out, s ? s : "", len);
                out[len] = '\0';
                if (verify_crc(c, name, d, crc32_elements(out, len, 1)) != 0) {
                    free(out);
                    out = NULL;
                }
            }
        }
        if (s)
            H5free_memory(s);
        H5Tclose(mt);
    } else if (n == 1) {
        /* fixed length: nul-padded in memory whatever the file's padding */
        const size_t size = H5Tget_size(ft);
        hid_t mt = H5Tcopy(ft);
        H5Tset_strpad(mt, H5T_STR_NULLPAD);
        out = calloc(size + 1, 1);
        if (!out) {
            fail(c, name, "cannot be read: out of memory for %zu bytes of text", size);
        } else if (H5Dread(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0) {
            fail(c, name, "cannot be read (text of %zu bytes)", size);
            free(out);
            out = NULL;
        } else if (verify_crc(c, name, d, crc32_elements(out, strlen(out), 1)) != 0) {
            free(out);
            out = NULL;
        }
        H5Tclose(mt);
    }
    if (ft >= 0)
        H5Tclose(ft);
    H5Dclose(d);
    return out;
}

/* A root attribute of one int32. */
static int write_root_i32(hid_t file, const char *name, int32_t v)
{
    return write_scalar_attr(file, name, H5T_STD_I32LE, H5T_NATIVE_INT32, &v);
}

/* The root attributes that make the file a checkpoint, the format last: every dataset carries
 * its CRC-32, then the format version. */
static int write_format(hid_t file)
{
    if (write_root_i32(file, CHECKSUMS_ATTR, 1) < 0)
        return -1;
    return write_root_i32(file, FORMAT_ATTR, LUB_CKPT_FORMAT);
}

int lub_ckpt_close(lub_ckpt *c, char *why, size_t len)
{
    char dummy[8];
    if (!why || len == 0) {
        why = dummy;
        len = sizeof dummy;
    }
    why[0] = '\0';
    if (!c)
        return 0;
    int rc = 0;
    char reason[160];
    if (c->writable && c->failed) {
        snprintf(why, len, "%s", c->failure);
        rc = -1;
    } else if (c->writable) {
        errno = 0;
        if (write_format(c->file) < 0) {
            failure_reason(errno, reason);
            snprintf(why, len, "checkpoint: cannot write the attribute \"%s\" of %s: %s",
                     FORMAT_ATTR, c->path, reason);
            rc = -1;
        } else {
            errno = 0;
            if (H5Fflush(c->file, H5F_SCOPE_LOCAL) < 0) {
                failure_reason(errno, reason);
                snprintf(why, len, "checkpoint: cannot flush %s: %s", c->path, reason);
                rc = -1;
            }
        }
    }
    errno = 0;
    if (H5Fclose(c->file) < 0) {
        failure_reason(errno, reason);
        if (rc == 0)
            snprintf(why, len, "checkpoint: cannot close %s: %s", c->path, reason);
        rc = -1;
    }
    free_ckpt(c);
    return rc;
}

/* Sets root text attribute name = text of file (replacing one of that name); 0 or -1. */
static int set_note(hid_t file, const char *name, const char *text)
{
    if (H5Aexists(file, name) > 0 && H5Adelete(file, name) < 0)
        return -1;
    hid_t t = text_type(H5T_CSET_UTF8);
    const int rc = write_scalar_attr(file, name, t, t, &text);
    H5Tclose(t);
    return rc;
}

int lub_ckpt_set_notes(const char *path, int n, const char *const *names, const char *const *texts,
                       char *why, size_t len)
{
    char dummy[8];
    if (!why || len == 0) {
        why = dummy;
        len = sizeof dummy;
    }
    why[0] = '\0';
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    char reason[160];
    errno = 0;
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (file < 0) {
        failure_reason(errno, reason);
        snprintf(why, len, "checkpoint: cannot open %s to note the build: %s", path, reason);
        return -1;
    }
    int rc = 0;
    for (int i = 0; i < n && rc == 0; ++i) {
        errno = 0;
        if (set_note(file, names[i], texts[i]) < 0) {
            failure_reason(errno, reason);
            snprintf(why, len, "checkpoint: cannot write the note \"%s\" of %s: %s", names[i], path,
                     reason);
            rc = -1;
        }
    }
    errno = 0;
    if (rc == 0 && H5Fflush(file, H5F_SCOPE_LOCAL) < 0) {
        failure_reason(errno, reason);
        snprintf(why, len, "checkpoint: cannot flush %s: %s", path, reason);
        rc = -1;
    }
    errno = 0;
    if (H5Fclose(file) < 0 && rc == 0) {
        failure_reason(errno, reason);
        snprintf(why, len, "checkpoint: cannot close %s: %s", path, reason);
        rc = -1;
    }
    return rc;
}

char *lub_ckpt_get_note(lub_ckpt *c, const char *name)
{
    if (!c || !name || H5Aexists(c->file, name) <= 0)
        return NULL;
    hid_t a = H5Aopen(c->file, name, H5P_DEFAULT);
    hid_t ft = a >= 0 ? H5Aget_type(a) : H5I_INVALID_HID;
    hid_t sp = a >= 0 ? H5Aget_space(a) : H5I_INVALID_HID;
    char *out = NULL;
    if (ft >= 0 && sp >= 0 && H5Tget_class(ft) == H5T_STRING &&
        H5Sget_simple_extent_npoints(sp) == 1) {
        if (H5Tis_variable_str(ft) > 0) {
            hid_t mt = text_type(H5Tget_cset(ft));
            char *v = NULL;
            if (H5Aread(a, mt, &v) >= 0 && v)
                out = strdup(v);
            if (v)
                H5free_memory(v);
            H5Tclose(mt);
        } else {
            const size_t size = H5Tget_size(ft);
            hid_t mt = H5Tcopy(ft);
            H5Tset_strpad(mt, H5T_STR_NULLPAD);
            out = calloc(size + 1, 1);
            if (out && H5Aread(a, mt, out) < 0) {
                free(out);
                out = NULL;
            }
            H5Tclose(mt);
        }
    }
    if (sp >= 0)
        H5Sclose(sp);
    if (ft >= 0)
        H5Tclose(ft);
    if (a >= 0)
        H5Aclose(a);
    return out;
}
