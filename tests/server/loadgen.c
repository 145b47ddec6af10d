#define _GNU_SOURCE
/* loadgen.c — a small loopback HTTP/1.1 load generator for the server benchmark.
 * N threads, each with one keep-alive connection to 127.0.0.1:PORT, send the same request
 * for S seconds (or until COUNT requests in total) and record every latency.
 * Prints: requests=... errors=... seconds=... rps=... p50_ms=... p99_ms=... max_ms=...
 * usage: lubd_loadgen PORT METHOD PATH TOKEN THREADS SECONDS COUNT [BODY] */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

typedef struct {
    int port;
    const char *req;
    size_t req_len;
    double until;
    atomic_long *budget;
    double *lat;
    long nlat, cap;
    long errors;
} worker;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int connect_to(int port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        if (fd >= 0)
            close(fd);
        return -1;
    }
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    return fd;
}

/* Sends the request and reads one response. Returns status or -1; *keep = keep-alive. */
static int roundtrip(int fd, const worker *w, int *keep)
{
    size_t sent = 0;
    while (sent < w->req_len) {
        ssize_t n = send(fd, w->req + sent, w->req_len - sent, MSG_NOSIGNAL);
        if (n <= 0)
            return -1;
        sent += (size_t)n;
    }
    char buf[65536];
    size_t have = 0;
    char *end = NULL;
    while (!end) {
        if (have == sizeof buf - 1)
            return -1;
        ssize_t n = recv(fd, buf + have, sizeof buf - 1 - have, 0);
        if (n <= 0)
            return -1;
        have += (size_t)n;
        buf[have] = '\0';
        end = strstr(buf, "\r\n\r\n");
    }
    int status = atoi(buf + 9);
    long clen = 0;
    char *cl = strcasestr(buf, "\r\nContent-Length:");
    if (cl && cl < end)
        clen = atol(cl + 17);
    char *conn = strcasestr(buf, "\r\nConnection: close");
    *keep = !(conn && conn < end);
    size_t body_have = have - (size_t)(end + 4 - buf);
    long left = clen - (long)body_have;
    while (left > 0) {
        ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n <= 0)
            return -1;
        left -= n;
    }
    return status;
}

static void *run(void *arg)
{
    worker *w = arg;
    int fd = -1;
    while (now() < w->until && atomic_fetch_sub(w->budget, 1) > 0) {
        if (fd < 0 && (fd = connect_to(w->port)) < 0) {
            ++w->errors;
            continue;
        }
        double t0 = now();
        int keep = 0;
        int st = roundtrip(fd, w, &keep);
        double dt = now() - t0;
        if (st < 200 || st >= 300)
            ++w->errors;
        else {
            if (w->nlat == w->cap) {
                w->cap = w->cap ? 2 * w->cap : 4096;
                w->lat = realloc(w->lat, (size_t)w->cap * sizeof *w->lat);
            }
            w->lat[w->nlat++] = dt;
        }
        if (st < 0 || !keep) {
            close(fd);
            fd = -1;
        }
    }
    if (fd >= 0)
        close(fd);
    return NULL;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 8) {
        fprintf(stderr, "usage: %s PORT METHOD PATH TOKEN THREADS SECONDS COUNT [BODY]\n", argv[0]);
        return 2;
    }
    int port = atoi(argv[1]), threads = atoi(argv[5]);
    double seconds = atof(argv[6]);
    long count = atol(argv[7]);
    const char *body = argc > 8 ? argv[8] : NULL;
    char req[8192];
    int n;
    if (body)
        n = snprintf(req, sizeof req,
                     "%s %s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nAuthorization: Bearer %s\r\n"
                     "Content-Type: application/json\r\nContent-Length: %zu\r\n\r\n%s",
                     argv[2], argv[3], port, argv[4], strlen(body), body);
    else
        n = snprintf(req, sizeof req,
                     "%s %s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nAuthorization: Bearer %s\r\n\r\n",
                     argv[2], argv[3], port, argv[4]);
    if (n <= 0 || (size_t)n >= sizeof req)
        return 2;
    atomic_long budget = count > 0 ? count : (1L << 60);
    worker *w = calloc((size_t)threads, sizeof *w);
    pthread_t *tid = calloc((size_t)threads, sizeof *tid);
    double t0 = now();
    for (int i = 0; i < threads; ++i) {
        w[i] = (worker){port, req, (size_t)n, t0 + seconds, &budget, NULL, 0, 0, 0};
        pthread_create(&tid[i], NULL, run, &w[i]);
    }
    long total = 0, errors = 0;
    for (int i = 0; i < threads; ++i) {
        pthread_join(tid[i], NULL);
        total += w[i].nlat;
        errors += w[i].errors;
    }
    double elapsed = now() - t0;
    double *all = malloc((size_t)(total > 0 ? total : 1) * sizeof *all);
    long k = 0;
    for (int i = 0; i < threads; ++i) {
        memcpy(all + k, w[i].lat, (size_t)w[i].nlat * sizeof *all);
        k += w[i].nlat;
        free(w[i].lat);
    }
    qsort(all, (size_t)total, sizeof *all, cmp);
    double p50 = total ? all[total / 2] : 0, p99 = total ? all[(long)(total * 0.99)] : 0;
    double mx = total ? all[total - 1] : 0;
    printf("requests=%ld errors=%ld seconds=%.3f rps=%.0f p50_ms=%.3f p99_ms=%.3f max_ms=%.3f\n",
           total, errors, elapsed, total / elapsed, p50 * 1e3, p99 * 1e3, mx * 1e3);
    free(all);
    free(w);
    free(tid);
    return errors ? 1 : 0;
}
