// The solver fingerprints of this build (cmake/solver_fingerprint.cmake), so two builds of the
// same solver code share them and a change to the solver changes them:
//   solver_fingerprint()      a hash of every file under solver/
//   source_fingerprint(file)  of a case: the solver without the case files, plus the case's own
//                             file (the file that registers it, CaseInfo::source), so adding or
//                             editing another case leaves it unchanged (case_fingerprint in
//                             cases/case.hpp finds it by case name)
// The runner records a job's case fingerprint with each attempt (stale results) and the job's
// checkpoints carry it (io/checkpoint.hpp: a checkpoint of other solver code is not continued).
// The environment variable SPH_RUNNER_SOLVER_FINGERPRINT overrides both (tests of other builds).
#pragma once

#include <string>

namespace sph {

std::string solver_fingerprint();
// `file`: a path ending in the case's file name (as __FILE__ gives it); a file that is not a case
// file of solver/cases/ (a test fixture elsewhere) gets solver_fingerprint().
std::string source_fingerprint(const std::string& file);

} // namespace sph
