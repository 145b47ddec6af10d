/* checkpoint_file.h — a typed store of named arrays in an HDF5 file: the state of a stopped
 * simulation, saved and reloaded bit for bit.
 *
 *   /<name>                    1-D dataset of float64 / int64 / int32 / uint8 (little-endian
 *                              in the file, native in memory; contiguous, not compressed);
 *                              names may contain '/' (intermediate groups are created)
 *   /<name>                    or a scalar UTF-8 string (lub_ckpt_put_text: variable length;
 *                              lub_ckpt_get_text also reads fixed-length strings)
 *   /<name> attribute "crc32"  (uint32) the CRC-32 (IEEE 802.3, zlib's crc32) of the dataset's
 *                              data in the file's byte order (little-endian), or of the text's
 *                              UTF-8 bytes; lub_ckpt_get and lub_ckpt_get_text check it and
 *                              refuse data that differs ("checkpoint: /system/x is damaged:
 *                              ...")
 *   root attribute "lubdem_checksums" = 1 (int32): every dataset carries its "crc32" (a
 *                              dataset without one is then damaged; a checkpoint written before
 *                              2026-12-07 has neither, and its data is read unchecked)
 *   root attribute "lubdem_checkpoint" = LUB_CKPT_FORMAT (int32), written by a successful
 *                              lub_ckpt_close after the others: a file whose writing did not
 *                              finish is not taken for a checkpoint
 *
 * Units: none; values are stored as given. Element counts are counts of elements, not bytes.
 * Values come back identical, bit for bit (NaN payloads, infinities and -0.0 included): file
 * and memory types differ at most in byte order. Data goes from the caller's array to the file
 * and back without copies (arrays of hundreds of MB need no extra memory).
 *
 * Ownership: lub_ckpt owns its HDF5 file handle; it keeps no pointer to anything passed in.
 * Errors: functions return 0 / -1 (or NULL), with a message naming the dataset in
 * lub_ckpt_error ("checkpoint: /x has 10 elements, expected 12"); HDF5's own error printing
 * is silenced. A put that fails (a refused write: no space, file too large, ...; an existing
 * name) voids the checkpoint: later puts do nothing and return -1 with the first failure's
 * message, and lub_ckpt_close returns -1 (the caller removes the file). Not thread-safe. */
#ifndef LUBDEM_CHECKPOINT_FILE_H
#define LUBDEM_CHECKPOINT_FILE_H

#include <stddef.h>
#include <stdint.h>

#define LUB_CKPT_FORMAT 1

typedef struct lub_ckpt lub_ckpt;
typedef enum { LUB_CKPT_F64, LUB_CKPT_I64, LUB_CKPT_I32, LUB_CKPT_U8 } lub_ckpt_type;

/* Creates (truncates) path for writing. NULL on failure with err[len] set (path and reason). */
lub_ckpt *lub_ckpt_create(const char *path, char *err, size_t len);
/* Opens an existing checkpoint read-only. NULL on failure with err[len] set (missing file, not
 * HDF5, not a lubdem checkpoint: no root attribute "lubdem_checkpoint"; another format version
 * than LUB_CKPT_FORMAT is an error naming both versions). */
lub_ckpt *lub_ckpt_open(const char *path, char *err, size_t len);

/* Writes a 1-D dataset `name` (may contain '/', intermediate groups created) of `count`
 * elements (count may be 0, data then may be NULL) of the given type from data. 0 / -1
 * (read-only file, existing name, refused write). */
int lub_ckpt_put(lub_ckpt *c, const char *name, lub_ckpt_type type, size_t count, const void *data);
/* Reads dataset `name` into data, which holds exactly `count` elements of `type`; -1 (message in
 * lub_ckpt_error) when it is missing, has another element count ("checkpoint: /x has 10
 * elements, expected 12"), another element type (class, size or signedness), or data whose
 * CRC-32 is not the one stored with it (data then holds what was read). */
int lub_ckpt_get(lub_ckpt *c, const char *name, lub_ckpt_type type, size_t count, void *data);
/* Element count of dataset `name` into *count; -1 when missing. */
int lub_ckpt_count(lub_ckpt *c, const char *name, size_t *count);
/* lub_ckpt_get_i64 of a member newer than some checkpoints: *v = absent when the checkpoint
 * does not hold `name` (no error set); -1 as lub_ckpt_get_i64 when it holds something else. */
int lub_ckpt_get_i64_or(lub_ckpt *c, const char *name, int64_t absent, int64_t *v);
/* 1 when the checkpoint holds `name`, 0 when not (no error set either way). */
int lub_ckpt_has(lub_ckpt *c, const char *name);

/* Convenience scalars: 1-D datasets of one element. */
int lub_ckpt_put_f64(lub_ckpt *c, const char *name, double v);
int lub_ckpt_put_i64(lub_ckpt *c, const char *name, int64_t v);
int lub_ckpt_get_f64(lub_ckpt *c, const char *name, double *v);
int lub_ckpt_get_i64(lub_ckpt *c, const char *name, int64_t *v);

/* UTF-8 text (e.g. a JSON document) as a scalar string dataset (put: variable length; get:
 * variable or fixed length). get returns a malloc'd copy (caller frees) or NULL with the error
 * set (also for a text whose CRC-32 is not the one stored with it). */
int lub_ckpt_put_text(lub_ckpt *c, const char *name, const char *text);
char *lub_ckpt_get_text(lub_ckpt *c, const char *name);

/* Notes: root text attributes of a checkpoint, outside its datasets (and their CRCs): what the
 * run driver records of the builds that ran the run (run_driver.c). lub_ckpt_set_notes opens
 * the closed checkpoint at path (written by lub_ckpt_create ... lub_ckpt_close) for writing and
 * sets n notes names[i] = texts[i] (UTF-8, replacing notes of those names); 0, or -1 with
 * why[len] (may be NULL) the reason (the file is then not to be published). lub_ckpt_get_note
 * returns a malloc'd copy of note `name` (caller frees; variable- or fixed-length text), NULL
 * when the checkpoint has none (no error set) or it is not text. */
int lub_ckpt_set_notes(const char *path, int n, const char *const *names, const char *const *texts,
                       char *why, size_t len);
char *lub_ckpt_get_note(lub_ckpt *c, const char *name);

/* The last error message ("" when none). */
const char *lub_ckpt_error(const lub_ckpt *c);

/* Closes and frees c (NULL: returns 0). For a file opened by create: writes the format
 * attribute and flushes; returns -1 when any put failed or the close failed (the caller then
 * removes the file), with why[len] (may be NULL) the reason; why is "" on success. */
int lub_ckpt_close(lub_ckpt *c, char *why, size_t len);

#endif
