/* Tests of the error bars of lub_rs_statistics (resuspension_statistics.h) on synthetic series
 * of instantaneous phi(y) profiles whose answer is known:
 *  1. every sample holds the same inventory, redistributed at random among the bins: eta_ii of
 *     the bottom bin, (inventory - phi_0 dy / 2)/Sh, moves only with phi_0, and with the bottom
 *     bin held fixed it is the same in every sample: its error is 0 (the propagation that
 *     assumed independent bins gave it the largest error of the profile);
 *  2. fully correlated bins (phi_k(y) = phi(y) + c_k, fewer than 32 samples: the naive SEM):
 *     eta_err of a bin with m bins above is (m + 1/2) dy/Sh SEM(c) and phi_coarse_err is
 *     SEM(c), exactly (the propagation gave sqrt(m + 1/4) dy/Sh SEM(c));
 *  3. independent noise of standard deviation s in every bin and sample (4096 samples, batch
 *     means): eta_err and phi_coarse_err are lub_stats_sem of the per-sample series summed here
 *     directly (to 1e-9), and near the analytic s dy/Sh sqrt(m + 1/4)/sqrt(n) and
 *     s sqrt(sum w^2)/sum w/sqrt(n) within the scatter of that estimator (a factor 1.6: its
 *     lag-1 correlation from 32 batch means scatters by ~0.18, clipped at 0);
 *  4. the suspension height's error (delta method on the per-sample profiles): with a small
 *     noise it is the naive SEM of the per-sample half-maximum heights to 1 %;
 *  5. height_steady judges the averaging window: a transient before it does not matter, a drift
 *     inside it does, and a transient of the whole series that outlasts the window's start is
 *     flagged (transient_in_window);
 *  6. the bed's base and the relative height increase on a constructed profile, by hand:
 *     y_b = 11/12 a (bottom half-maximum crossing), h = 6.5 a, h0 = 2.95/0.6 a, so
 *     (h - y_b - h0)/h0 = 8/59 (the floor-plane (h - h0)/h0 is 19/59); with a small noise
 *     the errors of y_b and of h - y_b are the naive SEMs of the per-sample values to 1 %;
 *  7. the law columns: law[i] is lub_dem_eta22(phi_coarse/phi_m), times
 *     lub_dem_lambda33(phi_coarse, 0.64) in the vorticity orientation, and law_log_rms the rms
 *     of ln(eta/law) over the bulk bins with eta_ii summed here by hand (eq. 6);
 *  8. the drag share: the mean of its per-sample series and that series' SEM, by hand for 5
 *     samples (naive: 0.03 +- sqrt(5e-5)) and against lub_stats_sem for 64 (batch means);
 *     NaN without the series;
 *  9. the velocity slope's error (delta method): with the same volumes in every sample it is
 *     the naive SEM of the per-sample slopes, exactly; with volumes that vary too, the
 *     per-sample change of the slope is the derivative, taken here by central differences of
 *     a least-squares fit written out here, of the slope of the window's sums moved towards
 *     that sample, times the sample count; its SEM naive (20 samples, by hand) and batch means
 *     (64, lub_stats_sem), a bulk bin no sphere crossed left out of both; NaN without the
 *     per-sample sums, the slope unchanged. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "continuum_normal_laws.h"
#include "resuspension_statistics.h"
#include "resuspension_analysis.h"
#include "stats.h"

static int failures = 0;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);                                        \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, "\n");                                                                 \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double uniform(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return ((double)(rng_state >> 11) + 0.5) / 9007199254740992.0;
}
static double gauss(void)
{
    return sqrt(-2.0 * log(uniform())) * cos(6.283185307179586 * uniform());
}

enum { NB = 24 };
static const double DY = 0.5, SH = 0.5, WINDOW = 2.0;
static int vorticity = 0; /* the orientation run_h passes */
/* the velocity inputs run_h passes (vx_volume NULL: zeros, no slope) */
static struct {
    const double *vx_volume, *vx_sum, *vx_samples, *drag_share;
    double bin_volume;
} vin;

typedef struct {
    double y[NB], phi[NB], phi_err[NB], cg[NB], cg_err[NB], eta[NB], eta_err[NB], law[NB];
    int bulk[NB];
    double mask[NB], vx[NB], rows[4 * NB], vol[NB], vsum[NB];
    double *s1, *s2, *s3, *height;
    lub_rs_stats st;
} result;

/* heights: nh samples, the last navg averaged (NULL: noise around 8 a, nh = navg) */
static void run_h(const double *samples, int64_t navg, const double *heights, int64_t nh, result *r)
{
    r->s1 = calloc((size_t)navg + 1, sizeof(double));
    r->s2 = calloc((size_t)navg + 1, sizeof(double));
    r->s3 = calloc((size_t)navg + 1, sizeof(double));
    if (!heights)
        nh = navg;
    r->height = calloc((size_t)nh, sizeof(double));
    for (int64_t k = 0; k < nh; ++k)
        r->height[k] = heights ? heights[k] : 8.0 + 0.1 * gauss();
    for (int i = 0; i < NB; ++i)
        r->vol[i] = r->vsum[i] = 0.0;
    const lub_rs_stats_input in = {.nb = NB,
                                   .dy = DY,
                                   .samples = samples,
                                   .navg = navg,
                                   .height = r->height,
                                   .nh = nh,
                                   .vx_volume = vin.vx_volume ? vin.vx_volume : r->vol,
                                   .vx_sum = vin.vx_volume ? vin.vx_sum : r->vsum,
                                   .vx_samples = vin.vx_samples,
                                   .bin_volume = vin.bin_volume,
                                   .drag_share = vin.drag_share,
                                   .shields = SH,
                                   .interface_width = 2.0,
                                   .floor_skip = 1.0,
                                   .phi_min = 0.05,
                                   .phi_m = 0.6,
                                   .phi_window = WINDOW,
                                   .vorticity = vorticity};
    const lub_rs_stats_profiles out = {.y = r->y,
                                       .phi = r->phi,
                                       .phi_err = r->phi_err,
                                       .phi_coarse = r->cg,
                                       .phi_coarse_err = r->cg_err,
                                       .eta = r->eta,
                                       .eta_err = r->eta_err,
                                       .law = r->law,
                                       .bulk = r->bulk,
                                       .bulk_mask = r->mask,
                                       .velocity_x = r->vx,
                                       .eta_vs_phi = r->rows,
                                       .scratch = r->s1,
                                       .scratch2 = r->s2,
                                       .scratch3 = r->s3};
    lub_rs_statistics(&in, &out, &r->st);
}

static void run(const double *samples, int64_t navg, result *r)
{
    run_h(samples, navg, NULL, 0, r);
}

static void release(result *r)
{
    free(r->s1);
    free(r->s2);
    free(r->s3);
    free(r->height);
}

/* the coarse-graining weights of bin i (the window cut at the ends) */
static double coarse_weight_factor(int i)
{
    const double lo = (i + 0.5) * DY - 0.5 * WINDOW, hi = lo + WINDOW;
    double sw = 0.0, sw2 = 0.0;
    for (int j = 0; j < NB; ++j) {
        const double w = fmin(hi, (j + 1) * DY) - fmax(lo, j * DY);
        if (w > 0) {
            sw += w;
            sw2 += w * w;
        }
    }
    return sqrt(sw2) / sw;
}

static double base(int i) { return i < 16 ? 0.5 : 0.0; }

/* The bed profile of cases 6 and 7: phi 0, 0.2, then 0.5 over bins 2-11 but 0.6 in bin 5, 0.4,
 * 0.2, then 0 */
static const double bed_profile[NB] = {0.0, 0.2, 0.5, 0.5, 0.5, 0.6, 0.5,
                                       0.5, 0.5, 0.5, 0.5, 0.5, 0.4, 0.2};

/* The naive SEM of x[0..n): sqrt(sample variance / n) */
static double naive_sem(const double *x, int n)
{
    double m = 0.0, v = 0.0;
    for (int k = 0; k < n; ++k)
        m += x[k] / n;
    for (int k = 0; k < n; ++k)
        v += (x[k] - m) * (x[k] - m) / (n - 1);
    return sqrt(v / n);
}

/* The least-squares slope of S_i/V_i against the bin centres over the bins with bulk[i] and
 * V_i > 0, from the centred sums: sum (y_i - ybar) v_i / sum (y_i - ybar)^2. */
static double fit_slope(const double *S, const double *V, const int *bulk)
{
    double n = 0.0, ybar = 0.0, num = 0.0, den = 0.0;
    for (int i = 0; i < NB; ++i)
        if (bulk[i] && V[i] > 0.0) {
            n += 1.0;
            ybar += (i + 0.5) * DY;
        }
    ybar /= n;
    for (int i = 0; i < NB; ++i)
        if (bulk[i] && V[i] > 0.0) {
            const double dyi = (i + 0.5) * DY - ybar;
            num += dyi * S[i] / V[i];
            den += dyi * dyi;
        }
    return num / den;
}

/* The first-order change of the slope with sample k: n d/de of fit_slope(S + e (s_k - S/n),
 * V + e (vol_k - V/n)) at e = 0, by central differences (vol = phi x bv). */
static double slope_change(const double *S, const double *V, const double *vs, const double *phi,
                           double bv, int n, int k, const int *bulk)
{
    const double e = 1e-5;
    double Sp[NB], Vp[NB], Sm[NB], Vm[NB];
    for (int i = 0; i < NB; ++i) {
        const double ds = vs[k * NB + i] - S[i] / n, dv = phi[k * NB + i] * bv - V[i] / n;
        Sp[i] = S[i] + e * ds;
        Sm[i] = S[i] - e * ds;
        /* a bin no sphere crossed stays empty */
        Vp[i] = V[i] > 0.0 ? V[i] + e * dv : 0.0;
        Vm[i] = V[i] > 0.0 ? V[i] - e * dv : 0.0;
    }
    return n * (fit_slope(Sp, Vp, bulk) - fit_slope(Sm, Vm, bulk)) / (2.0 * e);
}

/* Case 9's samples: n profiles of the bed (each bin's phi times 1 + vary g) with velocities
 * 0.8 y + 0.1 g, their sums (bin_volume bv) and the velocity sums of every sample; bin `empty`
 * (-1: none) with no volume in the window's sums (a bin no sphere crossed). */
static void velocity_samples(int n, double vary, double bv, int empty, double *phi, double *vs,
                             double *S, double *V)
{
    for (int i = 0; i < NB; ++i)
        S[i] = V[i] = 0.0;
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < NB; ++i) {
            phi[k * NB + i] = bed_profile[i] * (1.0 + vary * gauss());
            const double vol = phi[k * NB + i] * bv;
            vs[k * NB + i] = vol * (0.8 * (i + 0.5) * DY + 0.1 * gauss());
            if (i != empty) {
                S[i] += vs[k * NB + i];
                V[i] += vol;
            }
        }
}

/* n samples, each equal to prof, into s[n * NB] */
static void fill_samples(double *s, int n, const double *prof)
{
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < NB; ++i)
            s[k * NB + i] = prof[i];
}

int main(void)
{
    /* 1. fixed inventory, bottom bin fixed, the rest shuffled between pairs of bins */
    {
        enum { N = 64 };
        static double s[N * NB];
        for (int k = 0; k < N; ++k) {
            for (int i = 0; i < NB; ++i)
                s[k * NB + i] = base(i);
            for (int i = 1; i + 1 < 16; i += 2) {
                const double d = 0.1 * (uniform() - 0.5);
                s[k * NB + i] += d;
                s[k * NB + i + 1] -= d;
            }
        }
        result r;
        run(s, N, &r);
        CHECK(r.eta_err[0] <= 1e-12 * r.eta[0],
              "fixed inventory: eta_err of the bottom bin %.3g (eta %.4g), expected 0",
              r.eta_err[0], r.eta[0]);
        CHECK(r.eta_err[8] > 1e-4, "fixed inventory: eta_err of bin 8 %.3g should not vanish",
              r.eta_err[8]);
        CHECK(r.st.sem_batch_means == 1, "64 samples: batch means");
        release(&r);
    }
    /* 2. fully correlated bins, 20 samples: naive SEM, exact */
    {
        enum { N = 20 };
        static double s[N * NB];
        double c[N], cm = 0.0, cv = 0.0;
        for (int k = 0; k < N; ++k) {
            c[k] = 0.02 * gauss();
            cm += c[k] / N;
        }
        for (int k = 0; k < N; ++k) {
            cv += (c[k] - cm) * (c[k] - cm) / (N - 1);
            for (int i = 0; i < NB; ++i)
                s[k * NB + i] = base(i) + c[k];
        }
        const double sem_c = sqrt(cv / N);
        result r;
        run(s, N, &r);
        for (int i = 0; i < NB; ++i) {
            const double m = NB - 1 - i;
            const double want = (m + 0.5) * DY / SH * sem_c;
            CHECK(fabs(r.eta_err[i] - want) <= 1e-9 * want,
                  "correlated bins: eta_err[%d] %.10g, expected %.10g", i, r.eta_err[i], want);
            CHECK(fabs(r.cg_err[i] - sem_c) <= 1e-9 * sem_c,
                  "correlated bins: phi_coarse_err[%d] %.10g, expected %.10g", i, r.cg_err[i],
                  sem_c);
            CHECK(fabs(r.phi_err[i] - sem_c) <= 1e-9 * sem_c,
                  "correlated bins: phi_err[%d] %.10g, expected %.10g", i, r.phi_err[i], sem_c);
        }
        CHECK(r.st.sem_batch_means == 0, "20 samples: the naive SEM");
        release(&r);
    }
    /* 3. independent noise: batch means near the analytic SEM */
    {
        enum { N = 4096 };
        static double s[N * NB];
        const double sd = 0.03;
        for (int k = 0; k < N; ++k)
            for (int i = 0; i < NB; ++i)
                s[k * NB + i] = base(i) + sd * gauss();
        result r;
        run(s, N, &r);
        static double ser[N], scr[N];
        for (int i = 0; i < NB; ++i) {
            const double m = NB - 1 - i;
            for (int k = 0; k < N; ++k) {
                double e = 0.5 * s[k * NB + i];
                for (int j = i + 1; j < NB; ++j)
                    e += s[k * NB + j];
                ser[k] = e * DY / SH;
            }
            const double direct = lub_stats_sem(ser, N, scr);
            CHECK(fabs(r.eta_err[i] - direct) <= 1e-9 * direct,
                  "independent bins: eta_err[%d] %.10g, SEM of the per-sample eta %.10g", i,
                  r.eta_err[i], direct);
            const double want = sd * DY / SH * sqrt(m + 0.25) / sqrt((double)N);
            CHECK(fabs(log(r.eta_err[i] / want)) < log(1.6),
                  "independent bins: eta_err[%d] %.4g, expected %.4g", i, r.eta_err[i], want);
            const double want_cg = sd * coarse_weight_factor(i) / sqrt((double)N);
            CHECK(fabs(log(r.cg_err[i] / want_cg)) < log(1.6),
                  "independent bins: phi_coarse_err[%d] %.4g, expected %.4g", i, r.cg_err[i],
                  want_cg);
        }
        release(&r);
    }
    /* 4. height error: a peak at bin 3, a linear fall from bin 12 to 20, small noise */
    {
        enum { N = 24 };
        static double s[N * NB], hk[N];
        double hm = 0.0, hv = 0.0;
        for (int k = 0; k < N; ++k) {
            for (int i = 0; i < NB; ++i) {
                double b = i == 3 ? 0.6 : i < 12 ? 0.5 : i < 20 ? 0.5 - 0.0625 * (i - 11) : 0.0;
                s[k * NB + i] = b + (b > 0 ? 1e-4 * gauss() : 0.0);
            }
            double mx = 0.0;
            for (int i = 0; i < NB; ++i)
                mx = fmax(mx, s[k * NB + i]);
            hk[k] = lub_profile_height(s + k * NB, NB, 0.0, DY, 0.5 * mx);
            hm += hk[k] / N;
        }
        for (int k = 0; k < N; ++k)
            hv += (hk[k] - hm) * (hk[k] - hm) / (N - 1);
        const double want = sqrt(hv / N);
        result r;
        run(s, N, &r);
        CHECK(fabs(r.st.height - hm) < 1e-3, "height %.6g, mean of the samples' %.6g", r.st.height,
              hm);
        CHECK(fabs(r.st.height_err / want - 1.0) < 0.01,
              "height_err %.6g, SEM of the samples' %.6g", r.st.height_err, want);
        release(&r);
    }
    /* 5. height_steady over the averaging window (the last 200 of 400 samples) */
    {
        enum { N = 250, NH = 400 };
        static double s[N * NB], h[NH];
        for (int k = 0; k < N; ++k)
            for (int i = 0; i < NB; ++i)
                s[k * NB + i] = base(i);
        /* transient over the first 150 samples, then noise */
        for (int k = 0; k < NH; ++k)
            h[k] = 8.0 + (k < 150 ? 3.0 * (1.0 - k / 150.0) : 0.0) + 0.05 * gauss();
        result r;
        run_h(s, 200, h, NH, &r);
        CHECK(r.st.steady == 1 && r.st.transient_in_window == 0,
              "transient before the window: steady %d, transient_in_window %d (end %zu)",
              r.st.steady, r.st.transient_in_window, r.st.transient_end);
        release(&r);
        /* the same transient over the first 250 samples: into the window */
        for (int k = 0; k < NH; ++k)
            h[k] = 8.0 + (k < 250 ? 3.0 * (1.0 - k / 250.0) : 0.0) + 0.05 * gauss();
        run_h(s, 200, h, NH, &r);
        CHECK(r.st.transient_in_window == 1,
              "transient into the window (search limit) not flagged (end %zu)", r.st.transient_end);
        release(&r);
        /* a transient over the first 180 samples, the window from sample 150 */
        for (int k = 0; k < NH; ++k)
            h[k] = 8.0 + (k < 180 ? 3.0 * (1.0 - k / 180.0) : 0.0) + 0.05 * gauss();
        run_h(s, 250, h, NH, &r);
        CHECK(r.st.transient_in_window == 1, "transient into the window not flagged (end %zu)",
              r.st.transient_end);
        release(&r);
        /* a steady first part, then a drift through the whole window */
        for (int k = 0; k < NH; ++k)
            h[k] = 8.0 + (k >= 200 ? 0.004 * (k - 200) : 0.0) + 0.05 * gauss();
        run_h(s, 200, h, NH, &r);
        CHECK(r.st.steady == 0, "a drift through the averaging window judged steady");
        release(&r);
    }
    /* 6. bed base and relative height increase: phi 0, 0.2, then 0.5 over bins 2-11 but 0.6 in
     * bin 5, 0.4, 0.2, then 0; maximum 0.6, level 0.3 */
    {
        enum { N = 24 };
        static double s[N * NB], bk[N], tk[N];
        const double *prof = bed_profile;
        fill_samples(s, N, prof);
        result r;
        run(s, N, &r);
        /* y_b between the centres 0.75 (0.2) and 1.25 (0.5): 0.75 + 0.1/0.3 x 0.5 = 11/12;
         * h between 6.25 (0.4) and 6.75 (0.2): 6.25 + 0.1/0.2 x 0.5 = 6.5; inventory
         * 0.5 x 5.9 = 2.95, h0 = 2.95/0.6 = 59/12; (h - y_b - h0)/h0 = (2/3)/(59/12) = 8/59 */
        const double yb = 11.0 / 12.0, h = 6.5, h0 = 2.95 / 0.6;
        CHECK(fabs(r.st.bed_base - yb) < 1e-12, "bed base %.15g, expected %.15g", r.st.bed_base,
              yb);
        CHECK(fabs(r.st.height - h) < 1e-12, "height %.15g, expected %.15g", r.st.height, h);
        CHECK(fabs(r.st.relative_height_increase - 8.0 / 59.0) < 1e-12,
              "relative height increase %.15g, expected (h - y_b - h0)/h0 = 8/59 (the floor "
              "plane's (h - h0)/h0 is %.6g)",
              r.st.relative_height_increase, (h - h0) / h0);
        CHECK(fabs(r.st.relative_height_increase_floor_plane - 19.0 / 59.0) < 1e-12,
              "floor-plane relative height increase %.15g, expected %.15g",
              r.st.relative_height_increase_floor_plane, 19.0 / 59.0);
        CHECK(fabs(r.st.bed_base_err) < 1e-15 && fabs(r.st.relative_height_increase_err) < 1e-15,
              "identical samples: bed base error %.3g, relative error %.3g, expected 0",
              r.st.bed_base_err, r.st.relative_height_increase_err);
        release(&r);
        /* a small noise: the delta-method errors against the per-sample crossings' SEM */
        double bm = 0.0, dm = 0.0, bv = 0.0, dv = 0.0;
        for (int k = 0; k < N; ++k) {
            for (int i = 0; i < NB; ++i)
                s[k * NB + i] = prof[i] + (prof[i] > 0 ? 1e-4 * gauss() : 0.0);
            double mx = 0.0;
            for (int i = 0; i < NB; ++i)
                mx = fmax(mx, s[k * NB + i]);
            bk[k] = lub_profile_base(s + k * NB, NB, 0.0, DY, 0.5 * mx);
            tk[k] = lub_profile_height(s + k * NB, NB, 0.0, DY, 0.5 * mx) - bk[k];
            bm += bk[k] / N;
            dm += tk[k] / N;
        }
        for (int k = 0; k < N; ++k) {
            bv += (bk[k] - bm) * (bk[k] - bm) / (N - 1);
            dv += (tk[k] - dm) * (tk[k] - dm) / (N - 1);
        }
        run(s, N, &r);
        const double h0n = r.st.inventory / 0.6;
        CHECK(fabs(r.st.bed_base_err / sqrt(bv / N) - 1.0) < 0.01,
              "bed_base_err %.6g, SEM of the samples' %.6g", r.st.bed_base_err, sqrt(bv / N));
        CHECK(fabs(r.st.relative_height_increase_err * h0n / sqrt(dv / N) - 1.0) < 0.01,
              "relative_height_increase_err x h0 %.6g, SEM of the samples' h - y_b %.6g",
              r.st.relative_height_increase_err * h0n, sqrt(dv / N));
        release(&r);
    }
    /* 7. the law columns on the profile of case 6 (bulk bins 2-8: interface 6.5 - 2, floor
     * skip 1), both orientations */
    for (vorticity = 0; vorticity <= 1; ++vorticity) {
        enum { N = 4 };
        static double s[N * NB];
        const double *prof = bed_profile;
        fill_samples(s, N, prof);
        result r;
        run(s, N, &r);
        double s2 = 0.0;
        int nl = 0, bulk = 0;
        for (int i = 0; i < NB; ++i) {
            const double psi = r.cg[i] / 0.6;
            double want = psi < 1.0 ? lub_dem_eta22(psi) : NAN;
            if (vorticity)
                want *= lub_dem_lambda33(r.cg[i], 0.64);
            CHECK(isnan(want) ? isnan(r.law[i]) : fabs(r.law[i] - want) <= 1e-14 * want,
                  "vorticity %d: law[%d] %.15g, expected %.15g (phi_coarse %.6g)", vorticity, i,
                  r.law[i], want, r.cg[i]);
            const int k = i >= 2 && i <= 8;
            CHECK(r.bulk[i] == k, "vorticity %d: bin %d bulk %d, expected %d", vorticity, i,
                  r.bulk[i], k);
            bulk += k;
            if (k) {
                double eta = 0.5 * prof[i];
                for (int j = i + 1; j < NB; ++j)
                    eta += prof[j];
                eta *= DY / SH;
                const double d = log(eta / want);
                s2 += d * d;
                ++nl;
            }
        }
        const double rms = sqrt(s2 / nl);
        CHECK(bulk == 7 && r.st.bulk_bins == 7, "vorticity %d: %d bulk bins, expected 7", vorticity,
              r.st.bulk_bins);
        CHECK(fabs(r.st.law_log_rms - rms) <= 1e-12 * rms,
              "vorticity %d: law_log_rms %.15g, by hand %.15g", vorticity, r.st.law_log_rms, rms);
        release(&r);
    }
    vorticity = 0;
    /* 8. the drag share */
    {
        static double s[64 * NB];
        fill_samples(s, 64, bed_profile);
        const double share[5] = {0.01, 0.03, 0.02, 0.05, 0.04};
        result r;
        vin.drag_share = share;
        run(s, 5, &r);
        /* mean 0.03, deviations -0.02 0 -0.01 0.02 0.01: variance 0.001/4, SEM sqrt(5e-5) */
        CHECK(fabs(r.st.drag_share - 0.03) < 1e-15, "drag share %.17g, expected 0.03",
              r.st.drag_share);
        CHECK(fabs(r.st.drag_share_err - sqrt(5e-5)) < 1e-15,
              "drag share error %.17g, expected the naive SEM sqrt(5e-5) = %.17g",
              r.st.drag_share_err, sqrt(5e-5));
        release(&r);
        /* 64 samples of an AR(1) series: batch means */
        static double share64[64], scr[64];
        double x = 0.0, m = 0.0;
        for (int k = 0; k < 64; ++k) {
            x = 0.6 * x + 0.01 * gauss();
            share64[k] = 0.05 + x;
            m += share64[k];
        }
        m /= 64;
        const double want = lub_stats_sem(share64, 64, scr);
        vin.drag_share = share64;
        run(s, 64, &r);
        CHECK(fabs(r.st.drag_share - m) <= 1e-15, "drag share %.17g, mean %.17g", r.st.drag_share,
              m);
        CHECK(want > naive_sem(share64, 64) * 1.01 &&
                  fabs(r.st.drag_share_err - want) <= 1e-12 * want,
              "64 drag shares: error %.10g, lub_stats_sem %.10g (naive %.10g)", r.st.drag_share_err,
              want, naive_sem(share64, 64));
        release(&r);
        vin.drag_share = NULL;
        run(s, 64, &r);
        CHECK(isnan(r.st.drag_share) && isnan(r.st.drag_share_err),
              "no drag share series: %g +- %g, expected NaN", r.st.drag_share, r.st.drag_share_err);
        release(&r);
    }
    /* 9. the velocity slope's error; bulk bins 2-8 (case 7) */
    {
        enum { N = 64 };
        static double phi[N * NB], vs[N * NB], bk[N], ser[N], scr[N];
        double S[NB], V[NB];
        const double bv = 3.0;
        result r;
        vin.vx_volume = V;
        vin.vx_sum = S;
        vin.bin_volume = bv;
        /* the same volumes in every sample: d_k is the sample's own slope minus the window's */
        velocity_samples(20, 0.0, bv, -1, phi, vs, S, V);
        vin.vx_samples = vs;
        run(phi, 20, &r);
        for (int k = 0; k < 20; ++k) {
            double vol[NB];
            for (int i = 0; i < NB; ++i)
                vol[i] = phi[k * NB + i] * bv;
            bk[k] = fit_slope(vs + k * NB, vol, r.bulk);
        }
        CHECK(r.st.bulk_bins == 7, "velocity: %d bulk bins, expected 7", r.st.bulk_bins);
        CHECK(fabs(r.st.bulk_velocity_slope - fit_slope(S, V, r.bulk)) < 1e-12,
              "slope %.15g, by hand %.15g", r.st.bulk_velocity_slope, fit_slope(S, V, r.bulk));
        CHECK(fabs(r.st.bulk_velocity_slope_err / naive_sem(bk, 20) - 1.0) < 1e-9,
              "same volumes: slope error %.12g, naive SEM of the per-sample slopes %.12g",
              r.st.bulk_velocity_slope_err, naive_sem(bk, 20));
        release(&r);
        /* volumes that vary by 20 %: 20 samples (naive SEM), then 64 (batch means) with bin 5
         * empty in the window's sums */
        for (int c = 0; c < 2; ++c) {
            const int n = c == 0 ? 20 : N, empty = c == 0 ? -1 : 5;
            velocity_samples(n, 0.2, bv, empty, phi, vs, S, V);
            run(phi, n, &r);
            for (int k = 0; k < n; ++k)
                ser[k] = slope_change(S, V, vs, phi, bv, n, k, r.bulk);
            const double want = c == 0 ? naive_sem(ser, n) : lub_stats_sem(ser, (size_t)n, scr);
            CHECK(r.st.bulk_bins == 7 && (empty < 0 || isnan(r.vx[empty])),
                  "varying volumes, %d samples: %d bulk bins (7), velocity of the empty bin %g", n,
                  r.st.bulk_bins, empty < 0 ? 0.0 : r.vx[empty]);
            CHECK(fabs(r.st.bulk_velocity_slope - fit_slope(S, V, r.bulk)) < 1e-12,
                  "varying volumes, %d samples: slope %.15g, by hand %.15g", n,
                  r.st.bulk_velocity_slope, fit_slope(S, V, r.bulk));
            CHECK(fabs(r.st.bulk_velocity_slope_err / want - 1.0) < 1e-6,
                  "varying volumes, %d samples: slope error %.12g, SEM of the derivatives %.12g", n,
                  r.st.bulk_velocity_slope_err, want);
            release(&r);
        }
        /* without the per-sample sums: no error, the same slope */
        const double slope = fit_slope(S, V, r.bulk);
        vin.vx_samples = NULL;
        run(phi, N, &r);
        CHECK(isnan(r.st.bulk_velocity_slope_err) && fabs(r.st.bulk_velocity_slope - slope) < 1e-12,
              "no per-sample sums: slope %.15g +- %g, expected %.15g +- NaN",
              r.st.bulk_velocity_slope, r.st.bulk_velocity_slope_err, slope);
        release(&r);
        vin.vx_volume = NULL;
    }
    if (failures)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
