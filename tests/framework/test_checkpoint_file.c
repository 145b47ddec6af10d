/* test_checkpoint_file.c — the checkpoint store (checkpoint_file.h): arrays of every element
 * type come back bit for bit (NaN payloads, infinities, -0.0, extreme integers, empty arrays),
 * under nested names; a 100 kB UTF-8 JSON text comes back identical; a get of another count,
 * type or a missing name fails with a message naming the dataset; files that are not HDF5, not
 * checkpoints (no format attribute) or of another format version are refused; a failed put
 * (an existing name; a write beyond RLIMIT_FSIZE, EFBIG) makes the close fail.
 * Usage: test_checkpoint_file DIR (scratch files are written there). */
#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "checkpoint_file.h"
#include "framework_check.h"

static double f64_bits(uint64_t bits)
{
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

static int contains(const char *text, const char *part) { return strstr(text, part) != NULL; }

/* The reals that must survive: every kind of NaN, infinities, signed zeros, subnormals. */
enum { NF = 14, NI = 7, NU = 256, BIG = 1 << 20 };
static double reals[NF];
static const int64_t i64s[NI] = {INT64_MIN, -1, 0, 1, INT64_MAX, 0x0123456789abcdefLL, -42};
static const int32_t i32s[NI] = {INT32_MIN, -1, 0, 1, INT32_MAX, 0x01234567, -42};
static uint8_t u8s[NU];

static char *make_json(size_t bytes)
{
    char *s = malloc(bytes + 64);
    if (!s)
        return NULL;
    size_t n = 0;
    n += (size_t)sprintf(s + n, "{\"items\":[");
    for (int k = 0; n < bytes; ++k)
        n += (size_t)sprintf(s + n, "%s{\"k\":%d,\"σ_xy\":\"é\\u00e9 %.17g\"}", k ? "," : "", k,
                             1.0 / (k + 3));
    sprintf(s + n, "]}");
    return s;
}

static void write_all(const char *path, const double *big, const char *json)
{
    char err[512];
    lub_ckpt *c = lub_ckpt_create(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    CHECK(lub_ckpt_put(c, "reals", LUB_CKPT_F64, NF, reals) == 0);
    CHECK(lub_ckpt_put(c, "state/ints/i64", LUB_CKPT_I64, NI, i64s) == 0);
    CHECK(lub_ckpt_put(c, "state/ints/i32", LUB_CKPT_I32, NI, i32s) == 0);
    CHECK(lub_ckpt_put(c, "/state/bytes/u8", LUB_CKPT_U8, NU, u8s) == 0);
    CHECK(lub_ckpt_put(c, "a/b/c/d/e/big", LUB_CKPT_F64, BIG, big) == 0);
    /* empty arrays, with and without a pointer */
    CHECK(lub_ckpt_put(c, "empty/f64", LUB_CKPT_F64, 0, NULL) == 0);
    CHECK(lub_ckpt_put(c, "empty/i64", LUB_CKPT_I64, 0, i64s) == 0);
    CHECK(lub_ckpt_put(c, "empty/i32", LUB_CKPT_I32, 0, NULL) == 0);
    CHECK(lub_ckpt_put(c, "empty/u8", LUB_CKPT_U8, 0, NULL) == 0);
    CHECK(lub_ckpt_put_f64(c, "scalars/neg_zero", -0.0) == 0);
    CHECK(lub_ckpt_put_f64(c, "scalars/nan", reals[0]) == 0);
    CHECK(lub_ckpt_put_i64(c, "scalars/min", INT64_MIN) == 0);
    CHECK(lub_ckpt_put_text(c, "spec/json", json) == 0);
    CHECK(lub_ckpt_put_text(c, "spec/empty", "") == 0);
    char why[512] = "x";
    CHECK(lub_ckpt_close(c, why, sizeof why) == 0);
    CHECK(why[0] == '\0');
}

static void read_all(const char *path, const double *big, const char *json)
{
    char err[512];
    lub_ckpt *c = lub_ckpt_open(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    double r[NF];
    int64_t l[NI];
    int32_t i[NI];
    uint8_t u[NU];
    memset(r, 0x55, sizeof r);
    CHECK(lub_ckpt_get(c, "reals", LUB_CKPT_F64, NF, r) == 0);
    CHECK(memcmp(r, reals, sizeof r) == 0);
    CHECK(lub_ckpt_get(c, "/state/ints/i64", LUB_CKPT_I64, NI, l) == 0);
    CHECK(memcmp(l, i64s, sizeof l) == 0);
    CHECK(lub_ckpt_get(c, "state/ints/i32", LUB_CKPT_I32, NI, i) == 0);
    CHECK(memcmp(i, i32s, sizeof i) == 0);
    CHECK(lub_ckpt_get(c, "state/bytes/u8", LUB_CKPT_U8, NU, u) == 0);
    CHECK(memcmp(u, u8s, sizeof u) == 0);
    double *back = malloc(sizeof(double) * BIG);
    CHECK(back != NULL);
    if (back) {
        CHECK(lub_ckpt_get(c, "a/b/c/d/e/big", LUB_CKPT_F64, BIG, back) == 0);
        CHECK(memcmp(back, big, sizeof(double) * BIG) == 0);
    }
    free(back);
    size_t n = 99;
    CHECK(lub_ckpt_count(c, "a/b/c/d/e/big", &n) == 0 && n == BIG);
    const char *empties[4] = {"empty/f64", "empty/i64", "empty/i32", "empty/u8"};
    const lub_ckpt_type types[4] = {LUB_CKPT_F64, LUB_CKPT_I64, LUB_CKPT_I32, LUB_CKPT_U8};
    for (int k = 0; k < 4; ++k) {
        n = 99;
        CHECK(lub_ckpt_count(c, empties[k], &n) == 0 && n == 0);
        CHECK(lub_ckpt_get(c, empties[k], types[k], 0, NULL) == 0);
    }
    double d = 1.0;
    int64_t v = 0;
    CHECK(lub_ckpt_get_f64(c, "scalars/neg_zero", &d) == 0 && d == 0.0 && signbit(d));
    CHECK(lub_ckpt_get_f64(c, "scalars/nan", &d) == 0 && memcmp(&d, &reals[0], sizeof d) == 0);
    CHECK(lub_ckpt_get_i64(c, "scalars/min", &v) == 0 && v == INT64_MIN);
    char *text = lub_ckpt_get_text(c, "spec/json");
    CHECK(text && strcmp(text, json) == 0);
    free(text);
    text = lub_ckpt_get_text(c, "spec/empty");
    CHECK(text && text[0] == '\0');
    free(text);

    /* failures name the dataset */
    CHECK(lub_ckpt_get(c, "state/ints/i32", LUB_CKPT_I32, NI + 5, i) == -1);
    CHECK(strcmp(lub_ckpt_error(c), "checkpoint: /state/ints/i32 has 7 elements, expected 12") ==
          0);
    printf("wrong count: %s\n", lub_ckpt_error(c));
    CHECK(lub_ckpt_get(c, "state/ints/i32", LUB_CKPT_I32, 3, i) == -1);
    CHECK(contains(lub_ckpt_error(c), "/state/ints/i32 has 7 elements, expected 3"));
    CHECK(lub_ckpt_get(c, "state/ints/nothing", LUB_CKPT_I32, NI, i) == -1);
    CHECK(contains(lub_ckpt_error(c), "/state/ints/nothing") &&
          contains(lub_ckpt_error(c), "missing"));
    printf("missing: %s\n", lub_ckpt_error(c));
    CHECK(lub_ckpt_get(c, "no/such/group/x", LUB_CKPT_F64, 1, r) == -1);
    CHECK(contains(lub_ckpt_error(c), "/no/such/group/x"));
    CHECK(lub_ckpt_count(c, "state/nothing", &n) == -1);
    CHECK(contains(lub_ckpt_error(c), "/state/nothing"));
    CHECK(lub_ckpt_get(c, "state", LUB_CKPT_F64, 1, r) == -1); /* a group */
    CHECK(contains(lub_ckpt_error(c), "/state"));
    /* another type: class, size or signedness */
    CHECK(lub_ckpt_get(c, "reals", LUB_CKPT_I64, NF, l) == -1);
    CHECK(contains(lub_ckpt_error(c), "/reals") && contains(lub_ckpt_error(c), "float64"));
    printf("wrong type: %s\n", lub_ckpt_error(c));
    CHECK(lub_ckpt_get(c, "state/ints/i32", LUB_CKPT_I64, NI, l) == -1);
    CHECK(contains(lub_ckpt_error(c), "/state/ints/i32 holds int32, expected int64"));
    CHECK(lub_ckpt_get(c, "state/ints/i64", LUB_CKPT_F64, NI, r) == -1);
    CHECK(contains(lub_ckpt_error(c), "/state/ints/i64"));
    CHECK(lub_ckpt_get(c, "spec/json", LUB_CKPT_U8, 1, u) == -1);
    CHECK(contains(lub_ckpt_error(c), "/spec/json holds text"));
    CHECK(lub_ckpt_get_text(c, "reals") == NULL);
    CHECK(contains(lub_ckpt_error(c), "/reals"));
    CHECK(lub_ckpt_get_text(c, "spec/none") == NULL);
    CHECK(contains(lub_ckpt_error(c), "/spec/none"));
    /* read-only */
    CHECK(lub_ckpt_put_f64(c, "late", 1.0) == -1);
    CHECK(contains(lub_ckpt_error(c), "/late") && contains(lub_ckpt_error(c), "read-only"));
    CHECK(lub_ckpt_close(c, NULL, 0) == 0);
}

/* A file that is not a checkpoint is refused with a message naming it. */
static void refused(const char *dir)
{
    char path[4096], err[512];
    snprintf(path, sizeof path, "%s/ckpt_missing.h5", dir);
    remove(path);
    CHECK(lub_ckpt_open(path, err, sizeof err) == NULL);
    CHECK(contains(err, path) && contains(err, strerror(ENOENT)));
    printf("missing file: %s\n", err);

    snprintf(path, sizeof path, "%s/ckpt_text.h5", dir);
    FILE *fp = fopen(path, "w");
    CHECK(fp != NULL);
    if (fp) {
        fputs("{\"not\": \"hdf5\"}\n", fp);
        fclose(fp);
    }
    err[0] = '\0';
    CHECK(lub_ckpt_open(path, err, sizeof err) == NULL);
    CHECK(contains(err, path) && contains(err, "not an HDF5 file"));
    printf("not HDF5: %s\n", err);

    /* HDF5 without the attribute, then with another version */
    snprintf(path, sizeof path, "%s/ckpt_plain.h5", dir);
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(f >= 0);
    H5Fclose(f);
    err[0] = '\0';
    CHECK(lub_ckpt_open(path, err, sizeof err) == NULL);
    CHECK(contains(err, path) && contains(err, "not a lubdem checkpoint") &&
          contains(err, "lubdem_checkpoint"));
    printf("no attribute: %s\n", err);

    f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(f, "lubdem_checkpoint", H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT);
    const int version = LUB_CKPT_FORMAT + 1;
    CHECK(a >= 0 && H5Awrite(a, H5T_NATIVE_INT, &version) >= 0);
    H5Aclose(a);
    H5Sclose(sp);
    H5Fclose(f);
    err[0] = '\0';
    CHECK(lub_ckpt_open(path, err, sizeof err) == NULL);
    CHECK(contains(err, path) && contains(err, "version 2") && contains(err, "version 1"));
    printf("other version: %s\n", err);

    snprintf(path, sizeof path, "%s/no_such_dir/ckpt.h5", dir);
    err[0] = '\0';
    CHECK(lub_ckpt_create(path, err, sizeof err) == NULL);
    CHECK(contains(err, path));
    printf("cannot create: %s\n", err);
}

/* A checkpoint written by other means: fixed-length texts (nul- and space-padded) and
 * big-endian integers read back as well. */
static void foreign_writer(const char *dir)
{
    char path[4096], err[512];
    snprintf(path, sizeof path, "%s/ckpt_foreign.h5", dir);
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(f >= 0);
    if (f < 0)
        return;
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(f, "lubdem_checkpoint", H5T_STD_I64BE, sp, H5P_DEFAULT, H5P_DEFAULT);
    const int version = LUB_CKPT_FORMAT;
    CHECK(a >= 0 && H5Awrite(a, H5T_NATIVE_INT, &version) >= 0);
    H5Aclose(a);
    const H5T_str_t pads[2] = {H5T_STR_NULLPAD, H5T_STR_SPACEPAD};
    const char *names[2] = {"nullpad", "spacepad"};
    for (int k = 0; k < 2; ++k) {
        hid_t ft = H5Tcopy(H5T_C_S1);
        H5Tset_size(ft, 16);
        H5Tset_strpad(ft, pads[k]);
        hid_t mt = H5Tcopy(H5T_C_S1);
        H5Tset_size(mt, 16);
        H5Tset_strpad(mt, H5T_STR_NULLTERM);
        hid_t d = H5Dcreate2(f, names[k], ft, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        char text[16] = "{\"a\": 1}";
        CHECK(d >= 0 && H5Dwrite(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, text) >= 0);
        H5Dclose(d);
        H5Tclose(mt);
        H5Tclose(ft);
    }
    H5Sclose(sp);
    const hsize_t n = NI;
    sp = H5Screate_simple(1, &n, NULL);
    hid_t d = H5Dcreate2(f, "be", H5T_STD_I32BE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(d >= 0 && H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, i32s) >= 0);
    H5Dclose(d);
    H5Sclose(sp);
    H5Fclose(f);

    lub_ckpt *c = lub_ckpt_open(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    for (int k = 0; k < 2; ++k) {
        char *text = lub_ckpt_get_text(c, names[k]);
        CHECK(text && strcmp(text, "{\"a\": 1}") == 0);
        if (text && strcmp(text, "{\"a\": 1}") != 0)
            fprintf(stderr, "%s: [%s]\n", names[k], text);
        free(text);
    }
    int32_t back[NI];
    CHECK(lub_ckpt_get(c, "be", LUB_CKPT_I32, NI, back) == 0);
    CHECK(memcmp(back, i32s, sizeof back) == 0);
    CHECK(lub_ckpt_close(c, NULL, 0) == 0);
}

/* A put that fails voids the checkpoint: later puts fail, the close fails. */
static void existing_name(const char *dir)
{
    char path[4096], err[512], why[512];
    snprintf(path, sizeof path, "%s/ckpt_twice.h5", dir);
    lub_ckpt *c = lub_ckpt_create(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c)
        return;
    CHECK(lub_ckpt_put_f64(c, "x/y", 1.0) == 0);
    CHECK(lub_ckpt_put_f64(c, "x/y", 2.0) == -1);
    CHECK(contains(lub_ckpt_error(c), "/x/y exists already"));
    CHECK(lub_ckpt_put_f64(c, "x/z", 3.0) == -1);
    CHECK(contains(lub_ckpt_error(c), "/x/z") && contains(lub_ckpt_error(c), "/x/y"));
    CHECK(lub_ckpt_close(c, why, sizeof why) == -1);
    CHECK(contains(why, "/x/y exists already"));
    printf("void checkpoint: %s\n", why);
    /* not taken for a checkpoint (no format attribute) */
    CHECK(lub_ckpt_open(path, err, sizeof err) == NULL);
}

/* Beyond RLIMIT_FSIZE (the last test: the limit stays for the process): the put of a large
 * array fails with the system's reason, and the close fails. Small puts that HDF5 keeps in its
 * buffers until the close make the close fail too. */
static void file_too_large(const char *dir, const double *big)
{
    char path[4096], err[512], why[512];
    signal(SIGXFSZ, SIG_IGN); /* EFBIG instead of the signal, as lubdem does */
    struct rlimit lim;
    CHECK(getrlimit(RLIMIT_FSIZE, &lim) == 0);
    lim.rlim_cur = 256u << 10;
    CHECK(setrlimit(RLIMIT_FSIZE, &lim) == 0);

    snprintf(path, sizeof path, "%s/ckpt_big.h5", dir);
    lub_ckpt *c = lub_ckpt_create(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c)
        return;
    CHECK(lub_ckpt_put_i64(c, "system/n", 3) == 0);
    CHECK(lub_ckpt_put(c, "system/x", LUB_CKPT_F64, BIG, big) == -1);
    CHECK(contains(lub_ckpt_error(c), "/system/x") && contains(lub_ckpt_error(c), strerror(EFBIG)));
    printf("too large: %s\n", lub_ckpt_error(c));
    CHECK(lub_ckpt_put_i64(c, "system/step", 3) == -1);
    CHECK(lub_ckpt_close(c, why, sizeof why) == -1);
    CHECK(contains(why, "/system/x") && contains(why, strerror(EFBIG)));

    /* 300 kB of text and small arrays, each put may pass: the close cannot */
    snprintf(path, sizeof path, "%s/ckpt_big_text.h5", dir);
    c = lub_ckpt_create(path, err, sizeof err);
    CHECK(c != NULL);
    if (!c)
        return;
    char *json = make_json(300000);
    CHECK(json != NULL);
    const int put_rc = lub_ckpt_put_text(c, "spec", json ? json : "");
    free(json);
    const int put2 = lub_ckpt_put(c, "small", LUB_CKPT_F64, 100, big);
    why[0] = '\0';
    CHECK(lub_ckpt_close(c, why, sizeof why) == -1);
    CHECK(why[0] != '\0');
    printf("too large at close (puts %d %d): %s\n", put_rc, put2, why);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    const uint64_t bits[NF] = {
        0x7ff8000000000000u, /* quiet NaN */
        0xfff8000000000000u, /* negative quiet NaN */
        0x7ff8000000abcdefu, /* quiet NaN with a payload */
        0x7ff0000000000001u, /* signalling NaN */
        0x7ff0000000000000u, /* +inf */
        0xfff0000000000000u, /* -inf */
        0x8000000000000000u, /* -0.0 */
        0x0000000000000000u, /* +0.0 */
        0x0000000000000001u, /* smallest subnormal */
        0x800fffffffffffffu, /* largest negative subnormal */
        0x7fefffffffffffffu, /* DBL_MAX */
        0x3ff0000000000001u, /* 1 + ulp */
        0x3fb999999999999au, /* 0.1 */
        0xc00921fb54442d18u, /* -pi */
    };
    for (int k = 0; k < NF; ++k)
        reals[k] = f64_bits(bits[k]);
    for (int k = 0; k < NU; ++k)
        u8s[k] = (uint8_t)(255 - k);
    double *big = malloc(sizeof(double) * BIG);
    char *json = make_json(100000);
    if (!big || !json)
        return 2;
    uint64_t state = 88172645463325252u;
    for (int k = 0; k < BIG; ++k) { /* xorshift bit patterns, NaNs included */
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        big[k] = f64_bits(state);
    }
    CHECK(strlen(json) >= 100000);

    char path[4096];
    snprintf(path, sizeof path, "%s/ckpt_roundtrip.h5", argv[1]);
    write_all(path, big, json);
    read_all(path, big, json);
    refused(argv[1]);
    foreign_writer(argv[1]);
    existing_name(argv[1]);
    file_too_large(argv[1], big);
    free(big);
    free(json);
    return failures ? 1 : 0;
}
