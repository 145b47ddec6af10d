/* test_stress.c — virial stress of known configurations: pair parts, kinetic sign. */
#include <math.h>
#include <string.h>

#include "shear_test.h"
#include "stress.h"

int main(void)
{
    lub_stress s;
    lub_stress_zero(&s);
    /* two spheres along y, 1 below 2, distance 2.1; compressive normal contact force on 1
     * (pushing 1 away from 2: -y) of magnitude 3, lubrication normal force -1 along n;
     * tangential contact +x of 0.5, tangential lubrication +x of 0.25 */
    lub_pair_output o;
    memset(&o, 0, sizeof o);
    o.n = v3(0, 1, 0);
    o.fn_contact = -3.0;
    o.fn_lub = -1.0;
    o.fs_contact = v3(0.5, 0, 0);
    o.fs_lub = v3(0.25, 0, 0);
    vec3 l = v3(0, 2.1, 0);
    lub_stress_add_pair(&s, &o, l);
    lub_stress_add_kinetic(&s, 2.0, v3(0.1, 0.3, 0));
    lub_stress_scale(&s, 1.0 / 10.0);
    ST_CHECK(fabs(s.part[LUB_SP_NC][4] - (-3.0 * 2.1 / 10)) < 1e-15, "NC yy %g",
             s.part[LUB_SP_NC][4]);
    ST_CHECK(fabs(s.part[LUB_SP_NL][4] - (-2.1 / 10)) < 1e-15, "NL yy");
    /* sigma_xy = F_x l_y / V: positive for a shear force resisting gd>0 on the lower sphere */
    ST_CHECK(fabs(s.part[LUB_SP_SC][1] - 0.5 * 2.1 / 10) < 1e-15, "SC xy %g", s.part[LUB_SP_SC][1]);
    ST_CHECK(fabs(s.part[LUB_SP_SL][1] - 0.25 * 2.1 / 10) < 1e-15, "SL xy");
    ST_CHECK(s.part[LUB_SP_SC][3] == 0.0, "SC yx must be zero (force index first)");
    /* kinetic part carries the minus sign: -m v'v'/V */
    ST_CHECK(fabs(s.part[LUB_SP_KIN][0] - (-2.0 * 0.01 / 10)) < 1e-15, "KIN xx %g",
             s.part[LUB_SP_KIN][0]);
    ST_CHECK(fabs(s.part[LUB_SP_KIN][1] - (-2.0 * 0.03 / 10)) < 1e-15, "KIN xy");
    double tot[9];
    lub_stress_total(&s, tot);
    ST_CHECK(fabs(tot[4] - (-4.0 * 2.1 / 10 - 2.0 * 0.09 / 10)) < 1e-15, "total yy %g", tot[4]);
    ST_CHECK(fabs(tot[1] - (0.75 * 2.1 / 10 - 2.0 * 0.03 / 10)) < 1e-15, "total xy %g", tot[1]);
    lub_stress s2 = s;
    lub_stress_accumulate(&s2, &s);
    ST_CHECK(s2.part[LUB_SP_NC][4] == 2 * s.part[LUB_SP_NC][4], "accumulate");
    ST_DONE();
}
