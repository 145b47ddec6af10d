/* continuum_steady_curves.c — steady rheology of the continuum and DEM-seed laws
 * (see continuum_steady_curves.h). */
#include "continuum_steady_curves.h"

#include <math.h>

static int psi_ok(double psi, const char **why)
{
    if (!(psi > 0.0 && psi < 1.0)) {
        *why = "psi must be in ]0,1[";
        return 0;
    }
    return 1;
}

static void fill_texture(const lub_texture_params *p, double eta0, lub_steady_row *row)
{
    lub_texture_stress st = lub_texture_steady_stress(p);
    row->theta_e = 0.5 * atan(p->delta1); /* Prop. 4.2 / (3.9) */
    row->eta_rel = st.eta_app / eta0;
    row->alpha1 = st.n1 / st.eta_app;
    row->alpha2 = st.n2 / st.eta_app;
    row->pp_rel = st.pp / st.eta_app;
    row->eta_n2 = -st.n2 / eta0;
}

int lub_steady_m4(const lub_m4_laws *L, double psi, double phi_m, lub_steady_row *row,
                  const char **why)
{
    lub_texture_params p;
    if (!psi_ok(psi, why) || lub_m4_from_laws(L, psi, phi_m, 1.0, &p, why))
        return -1;
    row->psi = psi;
    row->phi = psi * phi_m;
    fill_texture(&p, 1.0, row);
    return 0;
}

int lub_steady_m3(const lub_m3_laws *L, double psi, double eta0, lub_steady_row *row,
                  const char **why)
{
    lub_texture_params p;
    if (!psi_ok(psi, why) || lub_m3_from_laws(L, psi * L->phi_m, eta0, &p, why))
        return -1;
    row->psi = psi;
    row->phi = psi * L->phi_m;
    fill_texture(&p, eta0, row);
    return 0;
}

int lub_steady_mm(const lub_mm_params *m, double psi, lub_steady_row *row, const char **why)
{
    if (!psi_ok(psi, why))
        return -1;
    double ep = lub_mm_eta_p(m, psi), en = lub_mm_eta_n(m, psi), er = 1.0 + ep;
    row->psi = psi;
    row->phi = psi * m->phi_m;
    row->theta_e = 0.0;
    row->eta_rel = er;
    row->alpha1 = -(1.0 - m->lambda_grad) * en / er;
    row->alpha2 = -(m->lambda_grad - m->lambda_vort) * en / er;
    row->pp_rel = (1.0 + m->lambda_grad + m->lambda_vort) * en / (3.0 * er);
    row->eta_n2 = (m->lambda_grad - m->lambda_vort) * en;
    return 0;
}

int lub_steady_dem(double psi, double phi_m, double phi_rcp, lub_steady_dem_row *row,
                   const char **why)
{
    if (!psi_ok(psi, why))
        return -1;
    double phi = psi * phi_m;
    row->psi = psi;
    row->phi = phi;
    row->eta_r = lub_dem_eta_r(phi, phi_m);
    row->eta22 = lub_dem_eta22(psi);
    row->lambda33 = lub_dem_lambda33(phi, phi_rcp);
    row->eta_n2 = (1.0 - row->lambda33) * row->eta22;
    row->alpha2 = -row->eta_n2 / row->eta_r;
    row->mu = row->eta_r / row->eta22;
    return 0;
}

void lub_steady_m4_limits(const lub_m4_laws *L, double *eta1_bar, double *alpha2_lim,
                          double *pp_lim)
{
    double d1 = L->delta1_bar, d2 = L->delta2_bar;
    *eta1_bar = L->omega + (1.0 + (L->beta1_bar + L->beta2_bar) / (d1 * d1)) * L->eta_e_bar;
    *alpha2_lim = L->eta_e_bar / *eta1_bar * (d1 * d2 + L->beta3_bar) / (d1 * d1);
    *pp_lim = -2.0 / 3.0 * (*alpha2_lim);
}

double lub_steady_m4_c2(const lub_m4_laws *L)
{
    return 3.0 * L->omega +
           L->a * (1.0 + L->b) * L->delta2_bar * L->eta_e_bar / ((1.0 - L->a) * (1.0 + L->a));
}
