/* The ThreadSanitizer check's own control (tsan_check.sh): with "race" two OpenMP threads
 * increment one int without synchronisation, which TSan must report; with "clean" they only
 * meet at a barrier, write disjoint elements and sum through a reduction, which it must not
 * report (with Archer telling TSan about the OpenMP runtime's synchronisation). */
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    const int race = argc > 1 && strcmp(argv[1], "race") == 0;
    int shared = 0;
    double a[256] = {0}, sum = 0;
#pragma omp parallel num_threads(2)
    {
        if (race)
            shared++;
#pragma omp barrier
#pragma omp for
        for (int i = 0; i < 256; ++i)
            a[i] = i;
#pragma omp for reduction(+ : sum)
        for (int i = 0; i < 256; ++i)
            sum += a[i];
    }
    printf("shared=%d sum=%g\n", shared, sum);
    return sum == 255.0 * 256.0 / 2.0 ? 0 : 1;
}
