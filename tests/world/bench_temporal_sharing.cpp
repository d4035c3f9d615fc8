// Would sharing U between neighbouring frames pay? For each window of W consecutive frames, the
// stored U S of the frames side by side, M = [U_1 S_1 ... U_W S_W] (pixels x sum of ranks), is what
// one shared basis would have to represent: its rank at the bake's truncation error (the smallest r
// whose discarded singular values hold at most target^2 of ||M||_F^2) against the sum of the
// frames' own ranks says how much of U a shared basis would save. Each frame would still need its
// own S V^T (columns x shared rank), so the saving is in U only. Window 1 is the baseline: the same
// re-truncation of each frame alone (what the stored ranks leave to discard at this target), so
// the gain of sharing is the difference between the two.
//   bench_temporal_sharing PACKAGE [window=2] [target=0.003]
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "world/package.h"

int main(int argc, char** argv) {
    using namespace firelook;
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s PACKAGE [window] [target]\n", argv[0]);
        return 2;
    }
    const int window = argc > 2 ? std::max(1, std::atoi(argv[2])) : 2;
    const double target = argc > 3 ? std::atof(argv[3]) : 0.003;
    const auto package = world::Package::open(argv[1]);
    const int frames = package->frameCount();
    std::vector<basis::ResidentFrame> resident;
    for (int slot = 0; slot < frames; ++slot)
        resident.push_back(package->loadResidentSlot(slot, std::pmr::get_default_resource(), nullptr));
    const size_t pixels = static_cast<size_t>(package->description().pixelCount());
    std::printf("window of %d frames, truncation target %.4g (relative Frobenius)\n", window, target);
    std::printf("%8s %14s %12s %10s\n", "frames", "sum of ranks", "shared rank", "U saved");
    double own_total = 0.0, shared_total = 0.0;
    for (int first = 0; first + window <= frames; first += window) {
        int columns = 0;
        for (int i = 0; i < window; ++i) columns += resident[first + i].rank;
        // Gram matrix of M (its eigenvalues are the squared singular values), in double.
        Eigen::MatrixXd m(static_cast<Eigen::Index>(pixels), columns);
        int c = 0;
        for (int i = 0; i < window; ++i) {
            const basis::ResidentFrame& f = resident[first + i];
            // U S = W step (u_scale = step / sigma, so U = W u_scale and U S = W step).
            for (int k = 0; k < f.rank; ++k, ++c) {
                double sigma2 = 0.0;
                for (int j = 0; j < f.columns; ++j) sigma2 += double(f.svt[size_t(j) * f.rank + k]) * f.svt[size_t(j) * f.rank + k];
                const double scale = f.u_scale[k] * std::sqrt(sigma2);
                for (size_t p = 0; p < pixels; ++p) m(static_cast<Eigen::Index>(p), c) = f.w[p * f.rank_stride + k] * scale;
            }
        }
        const Eigen::MatrixXd gram = m.transpose() * m;
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram, Eigen::EigenvaluesOnly);
        std::vector<double> values(solver.eigenvalues().data(), solver.eigenvalues().data() + columns);
        std::sort(values.begin(), values.end());  // ascending: discard from the front
        double total = 0.0;
        for (double v : values) total += std::max(v, 0.0);
        double discarded = 0.0;
        int kept = columns;
        for (double v : values) {
            if (discarded + std::max(v, 0.0) > target * target * total) break;
            discarded += std::max(v, 0.0);
            --kept;
        }
        own_total += columns;
        shared_total += kept;
        std::printf("%3d-%-4d %14d %12d %9.0f%%\n", package->frameNumber(first), package->frameNumber(first + window - 1),
                    columns, kept, 100.0 * (columns - kept) / columns);
    }
    std::printf("all windows: U columns %.0f -> %.0f (%.0f%% of U saved; each frame keeps its own S V^T)\n", own_total,
                shared_total, own_total > 0 ? 100.0 * (own_total - shared_total) / own_total : 0.0);
    return 0;
}
