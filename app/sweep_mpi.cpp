#include "sweep_mpi.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <exception>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "module_loader.hpp"
#include "mpi_module.hpp"
#include "summary.hpp"

namespace stiffmsa::cli {

namespace {

constexpr int kRoot = 0;
constexpr int kAnyRank = -1;   // a probe's source: MPI_ANY_SOURCE
constexpr int kTagAssign = 1;  // root -> rank: a block index, or kStop
constexpr int kTagBlock = 2;   // rank -> root: a solved block
constexpr std::uint64_t kStop = UINT64_MAX;
// Blocks a rank holds at once: one being solved, one waiting, so that it never waits for the
// root between blocks.
constexpr std::size_t kBlocksPerRank = 2;
// How long the root sleeps when no block has arrived: short against a block's solve (many
// milliseconds), long enough not to take a core from the solving threads.
constexpr auto kPollInterval = std::chrono::microseconds(200);

// ---- a block as bytes ---------------------------------------------------------------------

struct BlockHeader {
  std::uint64_t rows_bytes, summary_bytes, csv_bytes, plotted, threads;
  double seconds;
};

std::string pack(const SweepBlock& block) {
  std::string rows;
  serialize_rows(rows, block.rows);
  const std::string summary = block.summary.serialize();
  const BlockHeader header{rows.size(),          summary.size(), block.csv.size(),
                           block.plotted.size(), block.threads,  block.seconds};
  std::string out(reinterpret_cast<const char*>(&header), sizeof header);
  out += rows;
  out += summary;
  out += block.csv;
  out.append(reinterpret_cast<const char*>(block.plotted.data()),
             block.plotted.size() * sizeof(double));
  return out;
}

SweepBlock unpack(const std::string& bytes, const std::vector<SweepColumn>& columns) {
  BlockHeader header{};
  if (bytes.size() < sizeof header) throw Error("a block passed between MPI ranks is truncated");
  std::memcpy(&header, bytes.data(), sizeof header);
  if (bytes.size() != sizeof header + header.rows_bytes + header.summary_bytes + header.csv_bytes +
                          header.plotted * sizeof(double))
    throw Error("a block passed between MPI ranks has the wrong size");
  std::string_view rest(bytes);
  rest.remove_prefix(sizeof header);
  SweepBlock block{
      deserialize_rows(rest.substr(0, header.rows_bytes)),
      SweepSummary::deserialize(columns, rest.substr(header.rows_bytes, header.summary_bytes)),
      std::string(rest.substr(header.rows_bytes + header.summary_bytes, header.csv_bytes)),
      std::vector<double>(header.plotted),
      header.threads,
      header.seconds};
  std::memcpy(block.plotted.data(),
              rest.data() + header.rows_bytes + header.summary_bytes + header.csv_bytes,
              header.plotted * sizeof(double));
  return block;
}

// ---- MPI ------------------------------------------------------------------------------------

void check(bool succeeded, const char* what) {
  if (!succeeded) throw Error(std::string("MPI failed: ") + what);
}

// The MPI module, loaded at the first call (by a run that an MPI launcher started).
const MpiModule& mpi() {
  using Entry = const MpiModule* (*)();
  static const MpiModule& module = *reinterpret_cast<Entry>(
      module_entry(kMpiModuleFile, kMpiModuleEntry, "the MPI module (mpirun ... sweep)"))();
  return module;
}

// MPI from the start of the command to its end; MPI_Finalize on every way out but an abort.
class MpiSession {
 public:
  MpiSession() {
    // Only the main thread calls MPI; oneTBB's threads solve.
    if (!mpi().start(&rank_, &size_))
      throw Error("MPI could not start (MPI_Init_thread, MPI_Comm_rank or MPI_Comm_size failed)");
  }
  ~MpiSession() { mpi().finish(); }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

// The poses of block `index` of the plan.
std::pair<std::size_t, std::size_t> block_range(const SweepPlan& plan, std::uint64_t index) {
  const std::size_t first = plan.first + static_cast<std::size_t>(index) * plan.block;
  return {first, std::min(plan.block, plan.end - first)};
}

std::size_t block_count(const SweepPlan& plan) {
  return (plan.end - plan.first + plan.block - 1) / plan.block;
}

SweepBlock solve_block(const SweepPlan& plan, const BlockShape& shape, std::uint64_t index) {
  const auto [first, count] = block_range(plan, index);
  return make_block(shape, plan.solve(first, count), first);
}

// Test hook (tests/test_sweep_mpi.cpp): this rank dies by SIGKILL after sending its first
// block, as a rank whose node fails.
bool dies_after_first_block(int rank) {
  const char* value = std::getenv("STIFFMSA_TEST_KILL_RANK");
  return value != nullptr && std::atoi(value) == rank;
}

void send_assignment(int rank, std::uint64_t index) {
  check(mpi().send_index(index, rank, kTagAssign), "sending a block to a rank");
}

// A rank other than the root: solves the blocks it is given and sends them back.
void serve(const SweepPlan& plan, const BlockShape& shape, int rank) {
  std::deque<std::uint64_t> assigned;
  const auto receive = [&] {
    std::uint64_t index = 0;
    check(mpi().receive_index(&index, kRoot, kTagAssign), "receiving a block");
    if (index == kStop) return false;
    assigned.push_back(index);
    return true;
  };
  for (bool first = true;; first = false) {
    if (assigned.empty() && !receive()) return;
    bool waiting = true;
    while (waiting) {
      check(mpi().probe(kRoot, kTagAssign, &waiting, nullptr, nullptr), "probing");
      if (waiting && !receive()) return;
    }
    const std::uint64_t index = assigned.front();
    assigned.pop_front();
    const std::string bytes = pack(solve_block(plan, shape, index));
    check(mpi().send_bytes(bytes.data(), static_cast<int>(bytes.size()), kRoot, kTagBlock),
          "sending a solved block");
    if (first && dies_after_first_block(rank)) raise(SIGKILL);
  }
}

// The root's own share: a thread that solves the blocks the root gives itself, while the main
// thread talks to the other ranks and writes.
class LocalSolver {
 public:
  LocalSolver(const SweepPlan& plan, BlockShape shape)
      : shape_(std::move(shape)), thread_([this, &plan] { run(plan); }) {}
  ~LocalSolver() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  void assign(std::uint64_t index) {
    {
      std::lock_guard lock(mutex_);
      assigned_.push_back(index);
    }
    wake_.notify_all();
  }
  // A block solved since the last call, if any; rethrows the solver's failure.
  std::optional<std::pair<std::uint64_t, SweepBlock>> take() {
    std::lock_guard lock(mutex_);
    if (failure_) std::rethrow_exception(failure_);
    if (solved_.empty()) return std::nullopt;
    auto block = std::move(solved_.front());
    solved_.pop_front();
    return block;
  }

 private:
  void run(const SweepPlan& plan) {
    for (;;) {
      std::uint64_t index = 0;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stopping_ || !assigned_.empty(); });
        if (stopping_) return;
        index = assigned_.front();
        assigned_.pop_front();
      }
      try {
        SweepBlock block = solve_block(plan, shape_, index);
        std::lock_guard lock(mutex_);
        solved_.emplace_back(index, std::move(block));
      } catch (...) {
        std::lock_guard lock(mutex_);
        failure_ = std::current_exception();
        return;
      }
    }
  }

  BlockShape shape_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::uint64_t> assigned_;
  std::deque<std::pair<std::uint64_t, SweepBlock>> solved_;
  std::exception_ptr failure_;
  bool stopping_ = false;
  std::thread thread_;
};

struct RootRun {
  std::size_t threads = 1;
  double seconds = 0;
  // The root's main thread receiving and writing blocks (not waiting for them): what bounds a
  // run on many ranks, where it never waits.
  double root_cpu_seconds = 0;
};

double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// The root: hands out blocks as ranks return them, solves its own share and writes every block
// in pose order. At most kBlocksPerRank blocks per rank are out or waiting to be written.
RootRun lead(const SweepPlan& plan, SweepOutput& output, int ranks, bool quiet) {
  const std::size_t blocks = block_count(plan);
  const std::size_t window = kBlocksPerRank * static_cast<std::size_t>(ranks);
  std::vector<std::size_t> out(static_cast<std::size_t>(ranks), 0);  // blocks each rank holds
  std::map<std::uint64_t, SweepBlock> waiting;
  std::uint64_t next_to_assign = 0, next_to_write = 0;
  RootRun run;
  ProgressBar progress(!quiet);
  const auto start = std::chrono::steady_clock::now();
  LocalSolver local(plan, output.shape());

  const auto hand_out = [&] {
    for (int rank = 0; rank < ranks; ++rank)
      while (out[static_cast<std::size_t>(rank)] < kBlocksPerRank && next_to_assign < blocks &&
             next_to_assign < next_to_write + window) {
        if (rank == kRoot)
          local.assign(next_to_assign);
        else
          send_assignment(rank, next_to_assign);
        ++out[static_cast<std::size_t>(rank)];
        ++next_to_assign;
      }
  };
  const auto arrived = [&](int rank, std::uint64_t index, SweepBlock block) {
    --out[static_cast<std::size_t>(rank)];
    run.threads = std::max(run.threads, block.threads);
    waiting.emplace(index, std::move(block));
  };

  hand_out();
  while (next_to_write < blocks) {
    bool idle = true;
    bool waiting_block = false;
    int source = 0, bytes = 0;
    check(mpi().probe(kAnyRank, kTagBlock, &waiting_block, &source, &bytes), "probing");
    const double cpu_before = thread_cpu_seconds();
    if (waiting_block) {
      std::string buffer(static_cast<std::size_t>(bytes), '\0');
      check(mpi().receive_bytes(buffer.data(), bytes, source, kTagBlock),
            "receiving a solved block");
      SweepBlock block = unpack(buffer, output.summary().columns());
      const std::uint64_t index = (block.rows.first_pose - plan.first) / plan.block;
      arrived(source, index, std::move(block));
      idle = false;
    }
    while (auto solved = local.take()) {
      arrived(kRoot, solved->first, std::move(solved->second));
      idle = false;
    }
    for (auto it = waiting.find(next_to_write); it != waiting.end();
         it = waiting.find(next_to_write)) {
      output.write(it->second);
      waiting.erase(it);
      ++next_to_write;
      const auto [first, count] = block_range(plan, next_to_write - 1);
      progress.update(first + count - plan.first, plan.end - plan.first);
    }
    if (!idle) run.root_cpu_seconds += thread_cpu_seconds() - cpu_before;
    hand_out();
    if (idle) std::this_thread::sleep_for(kPollInterval);
  }
  for (int rank = 1; rank < ranks; ++rank) send_assignment(rank, kStop);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish();
  return run;
}

// The temporary files of the root, removed when mpirun ends the job (a rank died): a killed
// run leaves no half-written file behind and says why it stopped.
char temporary_files[2][4096];
extern "C" void on_termination(int) {
  static const char message[] =
      "stiffmsa: error: the MPI job was stopped before the sweep ended (a rank died: the launcher "
      "names it; or the job was cancelled); "
      "no output file was written\n";
  (void)!::write(STDERR_FILENO, message, sizeof message - 1);
  for (const char* path : temporary_files)
    if (path[0] != '\0') ::unlink(path);
  ::_exit(exit_cannot_solve);
}

}  // namespace

bool started_by_mpi_launcher() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(variable) != nullptr) return true;
  return false;
}

int run_sweep_over_ranks(const SweepCommand& command) {
  MpiSession session;
  // Every rank checks the command and reads the model; if any fails, all stop before solving,
  // and the error is printed once (by the root, or else by the ranks that failed).
  std::unique_ptr<PreparedSweep> prepared;
  std::unique_ptr<SweepOutput> output;  // the root's
  BlockShape shape;
  std::exception_ptr failure;
  int code = exit_success;
  try {
    if (command.view)
      throw UsageError(
          "--view with MPI ranks: the map holds every pose's result in one process; run the sweep "
          "without mpirun for it");
    prepared = prepare_sweep(command);
    if (session.rank() == kRoot) {
      output = std::make_unique<SweepOutput>(prepared->description, prepared->files,
                                             prepared->plan.first,
                                             prepared->plan.end - prepared->plan.first);
      shape = output->shape();
    } else {
      // The blocks as the root writes them.
      shape = {&prepared->description, prepared->files.plotted, !prepared->files.csv.empty(),
               !prepared->files.hdf5.empty()};
    }
  } catch (...) {
    failure = std::current_exception();
    code = exit_invalid_input;
  }
  int worst_code = code, root_code = code;
  mpi().largest_int(code, &worst_code);
  mpi().broadcast_int(&root_code, kRoot);
  if (worst_code != exit_success) {
    // The message is out before any rank leaves: mpirun stops the job at the first rank that
    // exits non-zero, which could cut off the reporting rank mid-way.
    int reported = worst_code;
    if (failure && (session.rank() == kRoot || root_code == exit_success)) {
      try {
        std::rethrow_exception(failure);
      } catch (...) {
        reported = report_current_exception();
      }
    }
    mpi().barrier();
    return reported;
  }

  try {
    if (session.rank() != kRoot) {
      serve(prepared->plan, shape, session.rank());
      return exit_success;
    }
    const auto temporary = output->temporary_files();
    for (std::size_t k = 0; k < temporary.size() && k < std::size(temporary_files); ++k)
      std::snprintf(temporary_files[k], sizeof temporary_files[k], "%s", temporary[k].c_str());
    signal(SIGTERM, on_termination);
    const RootRun run = lead(prepared->plan, *output, session.size(), command.quiet);
    auto extra = prepared->extra_summary.empty() ? nlohmann::json::object()
                                                 : nlohmann::json::parse(prepared->extra_summary);
    extra["ranks"] = session.size();
    const auto files = output->finish(run.threads, run.seconds, extra.dump());
    print_sweep_summary(std::cout, prepared->description, output->summary(), run.threads,
                        run.seconds, files, static_cast<std::size_t>(session.size()));
    // What bounds the run on many ranks: every row passes through the root.
    const std::size_t poses = prepared->plan.end - prepared->plan.first;
    char line[160];
    std::snprintf(line, sizeof line,
                  "  rank 0 spent %.3g s of CPU receiving and writing rows (%.3g us per row)\n",
                  run.root_cpu_seconds,
                  poses > 0 ? 1e6 * run.root_cpu_seconds / static_cast<double>(poses) : 0.0);
    std::cout << line;
    return exit_success;
  } catch (const std::exception& e) {
    // The other ranks wait for this one: only an abort ends them.
    print_error(std::cerr, "rank " + std::to_string(session.rank()) + ": " + e.what());
    output.reset();  // the root's unfinished files go; an abort runs no destructor
    mpi().abort(exit_invalid_input);
  }
  return exit_invalid_input;
}

}  // namespace stiffmsa::cli
