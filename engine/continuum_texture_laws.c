/* continuum_texture_laws.c — phi-laws and thesis tables of the texture models
 * (see continuum_texture_laws.h; equations (3.10), (3.16), (4.9); Tables 3.2, 3.3, 4.1, 4.2). */
#include "continuum_texture_laws.h"

#include <math.h>

double lub_texture_table_phi(int i)
{
    static const double phis[5] = {0.30, 0.40, 0.44, 0.47, 0.50};
    return (i >= 0 && i < 5) ? phis[i] : NAN;
}

lub_m3_laws lub_m3_laws_thesis(void)
{
    lub_m3_laws L = {
        .phi_m = 0.571, .delta_e = 0.661, .beta_bar = 0.152, .eta_e_bar = 0.0213, .omega = 0.652};
    return L;
}

lub_m4_laws lub_m4_laws_thesis(void)
{
    lub_m4_laws L = {.a = 0.6,
                     .b = 2.0,
                     .omega = 0.28,
                     .eta_e_bar = 0.21,
                     .delta1_bar = 0.27,
                     .delta2_bar = -0.8,
                     .beta1_bar = 0.05,
                     .beta2_bar = 0.45,
                     .beta3_bar = -0.19};
    return L;
}

double lub_m3_alpha(const lub_m3_laws *L, double phi)
{
    const double pi = 3.14159265358979323846;
    double r = phi / L->phi_m;
    double theta = L->delta_e * phi + (0.25 * pi - L->delta_e * L->phi_m) * r * r; /* (3.10) */
    return tan(2.0 * theta);
}

int lub_m3_from_laws(const lub_m3_laws *L, double phi, double eta0, lub_texture_params *out,
                     const char **why)
{
    if (!(phi > 0.0 && phi < L->phi_m)) {
        *why = "phi must be in ]0, phi_m[ (the M3 laws diverge at phi_m = 0.571)";
        return -1;
    }
    if (!(eta0 > 0.0)) {
        *why = "eta0 must be > 0";
        return -1;
    }
    double x = 1.0 - phi / L->phi_m;               /* > 0 */
    double beta = L->beta_bar / (x * x);           /* (3.16a) */
    double eta_e = L->eta_e_bar / (x * x * x * x); /* (3.16b) */
    double eta = eta0 * (1.0 - L->omega + (2.5 - 2.0 * L->omega / L->phi_m) * phi) +
                 eta0 * L->omega / (x * x); /* (3.16c) */
    *out = lub_texture_m3(lub_m3_alpha(L, phi), beta, eta_e, eta);
    return 0;
}

int lub_m4_from_laws(const lub_m4_laws *L, double psi, double phi_m, double eta0,
                     lub_texture_params *out, const char **why)
{
    if (!(psi > 0.0 && psi < 1.0)) {
        *why = "psi = phi/phi_m must be in ]0,1[ (the M4 laws diverge at psi = 1)";
        return -1;
    }
    if (!(phi_m > 0.0 && phi_m < 1.0) || !(eta0 > 0.0)) {
        *why = "phi_m must be in ]0,1[ and eta0 > 0";
        return -1;
    }
    double q = psi / (1.0 - psi); /* (1-psi)^{-1} - 1 */
    double f = q + L->b * psi;    /* (1-psi)^{-1} - (1 - b psi) */
    double om1 = 1.0 / ((1.0 - psi) * (1.0 - psi));
    out->a = L->a;
    out->delta1 = L->delta1_bar * f;   /* (4.9a) */
    out->delta2 = L->delta2_bar * f;   /* (4.9b) */
    out->beta1 = L->beta1_bar * q * q; /* (4.9c) */
    out->beta2 = L->beta2_bar * q * q;
    out->beta3 = L->beta3_bar * q * q;
    out->eta = eta0 * (1.0 - L->omega + psi * (2.5 * phi_m - 2.0 * L->omega) + L->omega * om1);
    out->eta_e = eta0 * L->eta_e_bar * psi * om1;
    return 0;
}

static int table_row(double phi, const char **why)
{
    for (int i = 0; i < 5; ++i)
        if (fabs(phi - lub_texture_table_phi(i)) < 1e-9)
            return i;
    *why = "phi must be one of the tabulated fractions 0.30, 0.40, 0.44, 0.47, 0.50";
    return -1;
}

int lub_m3_table32(double phi, lub_texture_params *out, double *torque_mNm, const char **why)
{
    /* Table 3.2 [L1790-1797]: T_m, alpha, beta, eta_e (Pa.s), eta (Pa.s) */
    static const double T[5][5] = {{0.07, 0.715, 0.79, 0.35, 3.5},
                                   {0.10, 1.33, 1.5, 2.9, 6.6},
                                   {0.25, 1.80, 3.0, 9.9, 11.5},
                                   {0.50, 2.37, 5.3, 21.0, 17.0},
                                   {2.00, 3.38, 9.3, 97.0, 79.0}};
    int i = table_row(phi, why);
    if (i < 0)
        return -1;
    *out = lub_texture_m3(T[i][1], T[i][2], T[i][3], T[i][4]);
    if (torque_mNm)
        *torque_mNm = T[i][0];
    return 0;
}

int lub_m4_table42(double phi, lub_texture_params *out, double *torque_mNm, const char **why)
{
    /* Table 4.2 [L2119-2127]: T, delta1, eta, eta_e, beta1, beta2, beta3, delta2 (a = 0.6);
     * the header "delta2_bar_i" is the per-phi delta2 (note E14). */
    static const double T[5][8] = {{0.07, 0.647, 3.55, 0.534, 0.0928, 1.26, -0.316, -2.02},
                                   {0.1, 1.20, 6.79, 2.53, 0.37, 3.87, -1.13, -4.03},
                                   {0.25, 1.69, 10.4, 5.74, 0.936, 10.7, -2.42, -5.27},
                                   {0.5, 2.43, 15.1, 9.71, 2.69, 23.5, -5.52, -6.26},
                                   {2.0, 4.36, 55.7, 37.2, 10.1, 90.4, -42.3, -12.4}};
    int i = table_row(phi, why);
    if (i < 0)
        return -1;
    out->a = 0.6;
    out->delta1 = T[i][1];
    out->eta = T[i][2];
    out->eta_e = T[i][3];
    out->beta1 = T[i][4];
    out->beta2 = T[i][5];
    out->beta3 = T[i][6];
    out->delta2 = T[i][7];
    if (torque_mNm)
        *torque_mNm = T[i][0];
    return 0;
}
