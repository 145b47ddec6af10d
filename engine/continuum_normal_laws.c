/* continuum_normal_laws.c — normal-viscosity and SBM laws (see continuum_normal_laws.h). */
#include "continuum_normal_laws.h"

#include <math.h>
#include <string.h>

int lub_normal_law_preset(const char *name, int direction, lub_normal_law *out)
{
    memset(out, 0, sizeof *out);
    out->kind = LUB_NLAW_POWER;
    out->direction = direction;
    int grad = direction == 2;
    if (strcmp(name, "zarraga") == 0) {
        out->n = 3.0;
        out->phi_m = 0.62;
        out->lambda = grad ? 1.36 : 0.62;
    } else if (strcmp(name, "boyer") == 0) {
        out->n = 2.0;
        out->phi_m = 0.585;
        out->lambda = grad ? 1.0 : 0.6;
    } else if (strcmp(name, "morris_boulay") == 0) {
        out->n = 2.0;
        out->phi_m = 0.68;
        out->lambda = grad ? 0.6 : 0.38;
    } else {
        return -1;
    }
    return 0;
}

double lub_dem_phi_m(double mu_m) { return 0.6301 - 0.0794 * (1.0 - exp(-mu_m / 0.4032)); }

double lub_dem_eta_r(double phi, double phi_m)
{
    const double mu1 = 0.36, mu2 = 0.7, I0 = 0.0133;
    double psi = phi / phi_m, s = psi / (1.0 - psi); /* phi_m/phi - 1 = 1/s */
    double s2 = s * s;
    return mu1 * s2 + (mu2 - mu1) * s2 / (1.0 + I0 * s2) + pow(1.0 - phi, -2.5);
}

double lub_dem_mu(double Iv, double phi_m)
{
    const double mu1 = 0.36, mu2 = 0.7, I0 = 0.0133;
    const double phi = phi_m / (1.0 + sqrt(Iv));
    return mu1 + (mu2 - mu1) / (1.0 + I0 / Iv) + Iv * pow(1.0 - phi, -2.5);
}

double lub_dem_eta22(double psi)
{
    double om = 1.0 - psi;
    return pow(psi, 9.0) / (om * om) + 150.0 * pow(psi, 10.0);
}

double lub_dem_lambda33(double phi, double phi_rcp)
{
    double u = phi / phi_rcp;
    return pow(u, 7.5) / (1e-3 + pow(u, 6.0));
}

double lub_normal_law_eta_s(const lub_normal_law *L, double s)
{
    if (!(s > 0.0))
        return 0.0;
    double psi = s / (1.0 + s);
    switch (L->kind) {
    case LUB_NLAW_POWER: return L->lambda * pow(s, L->n);
    case LUB_NLAW_DEM_SEED: {
        /* psi^9/(1-psi)^2 = psi^9 (1+s)^2 */
        double e22 = pow(psi, 9.0) * (1.0 + s) * (1.0 + s) + 150.0 * pow(psi, 10.0);
        if (L->direction == 3)
            e22 *= lub_dem_lambda33(psi * L->phi_m, L->phi_rcp);
        return e22;
    }
    case LUB_NLAW_OZENDA_M4: {
        if (L->direction == 3)
            return 0.0;
        lub_texture_params p;
        const char *why;
        if (lub_m4_from_laws(&L->m4, psi, L->phi_m, 1.0, &p, &why))
            return INFINITY;
        return -lub_texture_steady_stress(&p).n2;
    }
    }
    return 0.0;
}

double lub_normal_law_eta(const lub_normal_law *L, double phi)
{
    double psi = phi / L->phi_m;
    if (!(psi < 1.0))
        return INFINITY;
    return lub_normal_law_eta_s(L, psi / (1.0 - psi));
}

lub_mm_params lub_mm_default(void)
{
    lub_mm_params m = {
        .K_s = 0.1, .K_n = 0.75, .lambda_grad = 0.8, .lambda_vort = 0.5, .phi_m = 0.68};
    return m;
}

double lub_mm_eta_p(const lub_mm_params *m, double psi)
{
    double s = psi / (1.0 - psi);
    return 2.5 * m->phi_m * s + m->K_s * s * s; /* (2.41h) */
}

double lub_mm_eta_n(const lub_mm_params *m, double psi)
{
    double s = psi / (1.0 - psi);
    return m->K_n * s * s; /* (2.41i) */
}
