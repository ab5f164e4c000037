/* Prints the system maths library's results for a few inputs, so that tests/integration/portable_maths.rs
 * can check that the perturbed library is really loaded and really changes some of them. */
#include <math.h>
#include <stdio.h>

int main(void) {
    volatile float xs[] = {0.1f, 0.3f, 0.7f, 1.1f, 1.3f, 2.9f, -0.6f, 3.7f};
    for (int i = 0; i < 8; i++) {
        float x = xs[i];
        printf("%a %a %a %a\n", (double)sinf(x), (double)cosf(x), (double)tanf(x), (double)atan2f(x, 0.75f));
    }
    return 0;
}
