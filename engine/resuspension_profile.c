/* resuspension_profile.c — exact sphere–slab volumes and binned profiles
 * (resuspension_profile.h). */
#include "resuspension_profile.h"

#include <math.h>
#include <stddef.h>

#define RP_PI 3.14159265358979323846

/* Volume of the sphere below height h measured from its lowest point. */
static double cap_below(double h, double r)
{
    if (h <= 0.0)
        return 0.0;
    if (h >= 2.0 * r)
        return 4.0 / 3.0 * RP_PI * r * r * r;
    return RP_PI * h * h * (3.0 * r - h) / 3.0;
}

double lub_sphere_slab_volume(double yc, double r, double y1, double y2)
{
    if (!(y2 > y1))
        return 0.0;
    const double bottom = yc - r;
    return cap_below(y2 - bottom, r) - cap_below(y1 - bottom, r);
}

void lub_profile_add_sphere_weighted(double *vol, double *wsum, int n, double y0, double dy,
                                     double yc, double r, double value)
{
    int lo = (int)floor((yc - r - y0) / dy);
    int hi = (int)floor((yc + r - y0) / dy);
    if (lo < 0)
        lo = 0;
    if (hi > n - 1)
        hi = n - 1;
    for (int i = lo; i <= hi; ++i) {
        const double v = lub_sphere_slab_volume(yc, r, y0 + i * dy, y0 + (i + 1) * dy);
        vol[i] += v;
        if (wsum)
            wsum[i] += v * value;
    }
}

void lub_profile_add_sphere(double *vol, int n, double y0, double dy, double yc, double r)
{
    lub_profile_add_sphere_weighted(vol, NULL, n, y0, dy, yc, r, 0.0);
}

void lub_profile_normalise(const double *vol, int n, double dy, double area, double *phi)
{
    const double inv = 1.0 / (area * dy);
    for (int i = 0; i < n; ++i)
        phi[i] = vol[i] * inv;
}
