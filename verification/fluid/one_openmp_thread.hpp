#pragma once
// The fluid verification cases run on one OpenMP thread: their claims are
// numbers, not threading (bench_fluid covers that), and one thread keeps each
// case to seconds on the shared 2-core machine, where an oversubscribed
// OpenMP team spends most of its time in barriers. Included once by each
// case's executable; the setting is made before main() runs.
#include <omp.h>

namespace fdem::fluid_verification {

inline const int one_openmp_thread = [] {
  omp_set_num_threads(1);
  return 1;
}();

}  // namespace fdem::fluid_verification
