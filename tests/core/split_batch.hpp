// Shared by the batch tests: the settings of a batch that is split across threads at the tests'
// sizes.
#pragma once

#include <cstddef>

#include "aerial/batch.hpp"

namespace aerial_test {

/// KERNEL on THREADS threads, splitting a batch once it has MIN_PER_THREAD vertices a thread (the
/// tests' batches are far smaller than the default), at DISPLAY; no lighting.
inline aerial::BatchSettings split_batch(aerial::Kernel kernel, unsigned threads,
                                         std::size_t min_per_thread, aerial::Display display) {
    aerial::BatchSettings settings;
    settings.kernel = kernel;
    settings.threads = threads;
    settings.min_vertices_per_thread = min_per_thread;
    settings.display = display;
    return settings;
}

}  // namespace aerial_test
