#pragma once
// The MPI module (target stiffmsa_mpi_module): the few MPI calls of `mpirun -n N stiffmsa sweep`
// (app/sweep_mpi.cpp) built as a shared module that the command loads with dlopen when an MPI
// launcher started it, so that every other run does not load MPI's libraries (docs/library.md,
// "The command's modules"). The calls take plain types: no MPI header outside the module.
#include <cstdint>

namespace stiffmsa::cli {

inline constexpr const char* kMpiModuleFile = "stiffmsa_mpi.so";
inline constexpr const char* kMpiModuleEntry = "stiffmsa_mpi_module";

// Each call returns whether MPI succeeded; ranks and tags are MPI's, on MPI_COMM_WORLD.
struct MpiModule {
  // MPI_Init_thread (only the main thread calls MPI), then this process's rank and the size;
  // false where any of them fails (MPI finalised again where it had started).
  bool (*start)(int* rank, int* size) = nullptr;
  void (*finish)() = nullptr;  // MPI_Finalize
  void (*abort)(int code) = nullptr;
  bool (*send_index)(std::uint64_t index, int rank, int tag) = nullptr;
  bool (*receive_index)(std::uint64_t* index, int rank, int tag) = nullptr;
  bool (*send_bytes)(const void* data, int bytes, int rank, int tag) = nullptr;
  bool (*receive_bytes)(void* data, int bytes, int rank, int tag) = nullptr;
  // Whether a message with `tag` waits from `rank` (from any rank when `rank` < 0), and if so
  // from which rank and how many bytes (either may be null).
  bool (*probe)(int rank, int tag, bool* waiting, int* source, int* bytes) = nullptr;
  bool (*largest_int)(int value, int* largest) = nullptr;  // MPI_Allreduce with MPI_MAX
  bool (*broadcast_int)(int* value, int root) = nullptr;   // MPI_Bcast
  bool (*barrier)() = nullptr;
};

}  // namespace stiffmsa::cli
