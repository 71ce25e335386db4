// The MPI module's entry point (app/mpi_module.hpp); everything else is hidden.
#include "mpi_module.hpp"

#include <dlfcn.h>
#include <mpi.h>

namespace {

bool succeeded(int code) { return code == MPI_SUCCESS; }

bool start(int* rank, int* size) {
  // MPI's components are modules of their own that take symbols from MPI's library, which this
  // module's dlopen loaded locally: made global before they load.
  Dl_info library{};
  if (dladdr(reinterpret_cast<void*>(&MPI_Init_thread), &library) != 0 &&
      library.dli_fname != nullptr)
    dlopen(library.dli_fname, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD);
  int provided = 0;
  if (!succeeded(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided))) return false;
  if (succeeded(MPI_Comm_rank(MPI_COMM_WORLD, rank)) &&
      succeeded(MPI_Comm_size(MPI_COMM_WORLD, size)))
    return true;
  // Started but unable to say which rank this is: ended here, as no session will end it.
  MPI_Finalize();
  return false;
}

bool probe(int rank, int tag, bool* waiting, int* source, int* bytes) {
  int flag = 0;
  MPI_Status status;
  if (!succeeded(MPI_Iprobe(rank < 0 ? MPI_ANY_SOURCE : rank, tag, MPI_COMM_WORLD, &flag, &status)))
    return false;
  *waiting = flag != 0;
  if (!flag) return true;
  if (source != nullptr) *source = status.MPI_SOURCE;
  return bytes == nullptr || succeeded(MPI_Get_count(&status, MPI_BYTE, bytes));
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const stiffmsa::cli::MpiModule*
stiffmsa_mpi_module() {
  static const stiffmsa::cli::MpiModule module{
      start,
      [] { MPI_Finalize(); },
      [](int code) { MPI_Abort(MPI_COMM_WORLD, code); },
      [](std::uint64_t index, int rank, int tag) {
        return succeeded(MPI_Send(&index, 1, MPI_UINT64_T, rank, tag, MPI_COMM_WORLD));
      },
      [](std::uint64_t* index, int rank, int tag) {
        return succeeded(
            MPI_Recv(index, 1, MPI_UINT64_T, rank, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE));
      },
      [](const void* data, int bytes, int rank, int tag) {
        return succeeded(MPI_Send(data, bytes, MPI_BYTE, rank, tag, MPI_COMM_WORLD));
      },
      [](void* data, int bytes, int rank, int tag) {
        return succeeded(
            MPI_Recv(data, bytes, MPI_BYTE, rank, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE));
      },
      probe,
      [](int value, int* largest) {
        return succeeded(MPI_Allreduce(&value, largest, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD));
      },
      [](int* value, int root) {
        return succeeded(MPI_Bcast(value, 1, MPI_INT, root, MPI_COMM_WORLD));
      },
      [] { return succeeded(MPI_Barrier(MPI_COMM_WORLD)); },
  };
  return &module;
}
