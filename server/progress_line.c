/* progress_line.c — key=value parsing of a progress line. */
#include "progress_line.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int lubd_progress_parse(const char *line, lubd_progress *p)
{
    if (strncmp(line, "progress ", 9) != 0)
        return 0;
    p->fraction = -1;
    p->step = -1;
    p->steps_per_s = -1;
    p->eta_s = -1;
    const char *s = line + 9;
    while (*s) {
        while (*s == ' ')
            ++s;
        const char *eq = strchr(s, '=');
        if (!eq)
            break;
        size_t klen = (size_t)(eq - s);
        char *end;
        const char *v = eq + 1;
        if (klen == 8 && strncmp(s, "fraction", 8) == 0)
            p->fraction = strtod(v, &end);
        else if (klen == 4 && strncmp(s, "step", 4) == 0)
            p->step = strtoll(v, &end, 10);
        else if (klen == 11 && strncmp(s, "steps_per_s", 11) == 0)
            p->steps_per_s = strtod(v, &end);
        else if (klen == 5 && strncmp(s, "eta_s", 5) == 0)
            p->eta_s = strtod(v, &end);
        else
            end = (char *)v;
        s = end;
        while (*s && *s != ' ')
            ++s;
    }
    if (!(p->fraction >= 0)) /* also rejects NaN */
        return 0;
    if (p->fraction > 1)
        p->fraction = 1;
    if (!isfinite(p->eta_s))
        p->eta_s = -1;
    return 1;
}
