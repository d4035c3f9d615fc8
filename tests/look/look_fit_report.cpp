// Prints how the emission RBF width trades interpolation ripple against
// conditioning and step undershoot (analyzeEmissionFit), for the lead to quote.
// Not a test: run `look_fit_report` from the build folder.
#include <cstdio>

#include "look/emission_fit.h"

int main() {
    using firelook::analyzeEmissionFit;
    const int bin_counts[] = {8, 16, 32};
    const double widths[] = {0.6, 0.65, 0.7, 0.75, 0.8, 0.9, 1.0};
    std::printf("default width_in_bins = %.2f (kDefaultRbfWidth)\n", firelook::kDefaultRbfWidth);
    std::printf(
        "condition: 2-norm condition number of A_ji = phi_i(T_j)\n"
        "ripple: exact interpolant of a constant, max |L_e - 1| between the outer bin centres\n"
        "mid_ripple: the same between the two middle centres only (the Gaussian lattice's own ripple)\n"
        "end_dev: the same over the outer half bins [T_lo, T_0] and [T_n-1, T_hi] (roll-off)\n"
        "exact step: exact interpolant of a 0 -> 1 step between the middle bins, min below 0 / max above 1\n"
        "fitted step: the same through fitEmissionCoefficients (non-negative); fit_miss = max |L_e(T_j) - "
        "e_j|\n\n");
    std::printf("%4s %5s %10s %10s %10s %10s | %21s | %21s %10s\n", "bins", "width", "condition", "ripple",
                "mid_ripple", "end_dev", "exact step under/over", "fitted step under/over", "fit_miss");
    for (int bins : bin_counts) {
        for (double width : widths) {
            const firelook::EmissionFitReport r = analyzeEmissionFit(bins, width);
            std::printf(
                "%4d %5.2f %10.3f %9.3f%% %9.3f%% %9.3f%% | %9.3f%% %9.3f%% | %9.3f%% %9.3f%% %9.3f%%\n",
                r.bins, r.width_in_bins, r.condition_number, 100 * r.constant_ripple,
                100 * r.constant_ripple_middle, 100 * r.constant_end_deviation, 100 * r.step_undershoot_exact,
                100 * r.step_overshoot_exact, 100 * r.step_undershoot_fitted, 100 * r.step_overshoot_fitted,
                100 * r.step_center_error_fitted);
        }
        std::printf("\n");
    }
    return 0;
}
