/* sha256.h — SHA-256 (FIPS 180-4), implemented here (no crypto library is linked).
 * Used for token hashes, request fingerprints (Idempotency-Key) and result checksums.
 * Pure functions; the context is owned by the caller; no allocation, no failure modes. */
#ifndef LUBD_SHA256_H
#define LUBD_SHA256_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint32_t h[8];
    uint64_t length; /* bytes hashed so far */
    uint8_t block[64];
    size_t fill; /* bytes waiting in block */
} lubd_sha256;

void lubd_sha256_init(lubd_sha256 *c);
void lubd_sha256_update(lubd_sha256 *c, const void *data, size_t n);
void lubd_sha256_final(lubd_sha256 *c, uint8_t out[32]);
/* One-shot helper: writes 64 lowercase hex digits + NUL into hex. */
void lubd_sha256_hex(const void *data, size_t n, char hex[65]);
void lubd_hex_encode(const uint8_t *in, size_t n, char *out /* 2n+1 */);
/* 1 when s is exactly 2n lowercase hex digits (a job id: n = 16), else 0. */
int lubd_is_hex(const char *s, size_t n);
/* Constant-time equality of two equal-length buffers (1 = equal). */
int lubd_ct_equal(const void *a, const void *b, size_t n);

#endif
