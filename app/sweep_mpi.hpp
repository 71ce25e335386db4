#pragma once
// `mpirun -n N stiffmsa sweep ...` (builds with STIFFMSA_WITH_MPI): the poses are handed out in
// blocks to the ranks as they finish (oneTBB threads inside each rank), and the first rank
// writes every block in pose order, so the files are those of one process (docs/cluster.md).
#include "sweep_command.hpp"

namespace stiffmsa::cli {

// Whether an MPI launcher (mpirun, mpiexec, srun) started this process; a plain start of an
// MPI build runs as one process without initialising MPI.
bool started_by_mpi_launcher();

int run_sweep_over_ranks(const SweepCommand& command);

}  // namespace stiffmsa::cli
