// Sweep throughput: stiffmsa::sweep over a fixed 2-D grid of each parametric example, with 1
// and with 2 threads, and where one pose's time goes (building the member from the file's
// expressions vs solving it); then pairs of examples swept in turn on one thread. Prints one
// JSON line per model and per pair; bench/summarize.py makes the "Sweeps" tables of
// bench/README.md from them.
//
//   stiffmsa_sweep [--repeats R] [auto|sparse_lu|umfpack|klu]
//
// A separate program, not a Google Benchmark case, because run.sh pins stiffmsa_bench to one
// core and Google Benchmark reports CPU time; here the process must own both cores and the
// figure that matters is wall time. Each sweep is repeated R times (default 7), alternating
// 1 and 2 threads so that a slow spell of this shared VM hits both alike; every repeat is
// printed, and the summary takes the lowest and the median.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of every thread of the process: with 2 threads, CPU / wall shows whether the
// second core was really working (and not waiting for work or descheduled by the host).
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Time the hypervisor gave the two vCPUs to someone else (the "steal" column of /proc/stat,
// in clock ticks, both cores together): a sweep that lost many ticks was slowed by the host.
long steal_ticks() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  long user, nice, system, idle, iowait, irq, softirq, steal;
  if (stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal)
    return steal;
  return -1;
}

struct Case {
  std::string key;   // short name in the results
  std::string file;  // under examples/
  std::vector<stiffmsa::GridAxis> grid;
};

// The grids of the examples' own "stiffmsa sweep" comments (3-RPR 41×39, tripteron 31×31); the
// Delta robot, with ball joints at both ends of its rods and with a universal joint at their tops,
// over a 21×21 grid of the same horizontal square as its comment's map.
const std::vector<stiffmsa::GridAxis> kDeltaGrid{{"px", -0.3, 0.3, 21}, {"py", -0.3, 0.3, 21}};
std::vector<Case> cases() {
  return {{"3rpr", "planar-3rpr-parametric.yaml", {{"x", 0.1, 0.9, 41}, {"y", 0.05, 0.8, 39}}},
          {"tripteron", "tripteron-parametric.yaml", {{"px", 0.1, 0.4, 31}, {"py", 0.1, 0.4, 31}}},
          {"delta-ss", "delta-parametric.yaml", kDeltaGrid},
          {"delta-us", "delta-us-parametric.yaml", kDeltaGrid}};
}

// Two cases whose sweeps are compared on one thread, alternated so that a slow spell of the
// shared machine hits both alike: the Delta robot with and without idle rod spins.
struct Pair {
  std::string first, second;  // Case keys
};
const std::vector<Pair> kPairs{{"delta-ss", "delta-us"}};

// Every parameter's value at each pose: the family's defaults with the swept ones replaced,
// as the sweep hands them to its builders.
std::vector<std::vector<double>> full_values(const stiffmsa::ModelFamily& family,
                                             const stiffmsa::PoseTable& poses) {
  std::vector<std::size_t> swept;
  for (const auto& name : poses.parameters) swept.push_back(*family.find_parameter(name));
  std::vector<std::vector<double>> all(poses.size(), family.default_values());
  for (std::size_t i = 0; i < poses.size(); ++i)
    for (std::size_t k = 0; k < swept.size(); ++k) all[i][swept[k]] = poses.pose(i)[k];
  return all;
}

std::string json_list(const std::vector<double>& values) {
  std::ostringstream out;
  out.precision(6);
  out << '[';
  for (std::size_t i = 0; i < values.size(); ++i) out << (i ? ", " : "") << values[i];
  out << ']';
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage = "usage: stiffmsa_sweep [--repeats R] [auto|sparse_lu|umfpack|klu]\n";
  stiffmsa::SweepOptions options;  // the default solve options, as `stiffmsa sweep` uses them
  int repeats = 7;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (const auto kind = stiffmsa::solver_kind_from_string(arg);
               kind && stiffmsa::solver_available(*kind)) {
      options.solve.solver = *kind;
    } else {
      std::cerr << "stiffmsa_sweep: unknown or unavailable '" << arg << "'\n" << usage;
      return 2;
    }
  }

  for (const Case& c : cases()) {
    const stiffmsa::ModelFamily family =
        stiffmsa::load_model_family(std::string(STIFFMSA_EXAMPLES_DIR) + "/" + c.file);
    const stiffmsa::PoseTable poses = stiffmsa::grid_poses(c.grid);

    // One untimed sweep first: page faults of fresh memory, TBB's worker threads, caches.
    options.threads = 2;
    const stiffmsa::SweepResult first = stiffmsa::sweep(family, poses, options);
    std::map<std::string, int> statuses;
    for (const auto& r : first.results) ++statuses[stiffmsa::to_string(r.status)];

    // Whole sweep() calls, wall and process CPU time, 1 and 2 threads in turn.
    std::map<std::size_t, std::vector<double>> wall, cpu, steal;
    for (int r = 0; r < repeats; ++r)
      for (std::size_t threads : {std::size_t{1}, std::size_t{2}}) {
        options.threads = threads;
        const long steal_before = steal_ticks();
        const double cpu_before = process_cpu_seconds();
        const auto start = Clock::now();
        const stiffmsa::SweepResult result = stiffmsa::sweep(family, poses, options);
        wall[threads].push_back(seconds_since(start));
        cpu[threads].push_back(process_cpu_seconds() - cpu_before);
        steal[threads].push_back(static_cast<double>(steal_ticks() - steal_before));
        if (result.threads != threads)
          std::cerr << "stiffmsa_sweep: asked for " << threads << " threads, got " << result.threads
                    << "\n";
      }

    // Where one pose goes, on one thread: writing every member's values with one writer (what
    // each sweep thread does), then solving them, kept aside untimed, with one workspace of the
    // structure.
    const auto values = full_values(family, poses);
    auto start = Clock::now();
    const stiffmsa::Structure structure = family.structure();
    stiffmsa::ModelFamily::ValueWriter write = family.make_writer(structure);
    const double make_builder_s = seconds_since(start);
    std::vector<double> build_s, solve_s;
    std::vector<double> member(structure.value_count());
    std::vector<stiffmsa::Diagnostic> warnings;
    for (int r = 0; r < repeats; ++r) {
      start = Clock::now();
      for (const auto& v : values) {
        try {
          write(v, member, warnings);
        } catch (const stiffmsa::InputError&) {
          // an invalid pose (e.g. out of reach): the sweep pays for the attempt too
        }
      }
      build_s.push_back(seconds_since(start));
    }
    std::vector<std::vector<double>> members;
    members.reserve(values.size());
    for (const auto& v : values) {
      try {
        write(v, member, warnings);
        members.push_back(member);
      } catch (const stiffmsa::InputError&) {
      }
    }
    stiffmsa::Workspace workspace(structure);
    for (int r = 0; r < repeats; ++r) {
      start = Clock::now();
      for (const auto& built : members) {
        try {
          stiffmsa::solve(workspace, built, options.solve);
        } catch (const stiffmsa::InputError&) {
          // an invalid pose (e.g. out of reach): the sweep pays for the attempt too
        } catch (const stiffmsa::SingularModelError&) {
          // a singular or free-moving pose: the sweep pays for the attempt too
        }
      }
      solve_s.push_back(seconds_since(start));
    }

    std::ostringstream status_json;
    for (const auto& [name, n] : statuses)
      status_json << (status_json.tellp() ? ", " : "") << '"' << name << "\": " << n;
    std::printf(
        "{\"model\": \"%s\", \"file\": \"%s\", \"solver\": \"%s\", \"grid\": \"%s=%g:%g:%zu "
        "%s=%g:%g:%zu\", "
        "\"poses\": %zu, \"statuses\": {%s}, "
        "\"wall_s_1\": %s, \"wall_s_2\": %s, \"cpu_s_1\": %s, \"cpu_s_2\": %s, \"steal_ticks_1\": "
        "%s, "
        "\"steal_ticks_2\": %s, \"make_builder_s\": %.6g, \"build_s\": %s, \"solve_s\": %s}\n",
        c.key.c_str(), c.file.c_str(), stiffmsa::to_string(options.solve.solver),
        c.grid[0].parameter.c_str(), c.grid[0].start, c.grid[0].stop, c.grid[0].count,
        c.grid[1].parameter.c_str(), c.grid[1].start, c.grid[1].stop, c.grid[1].count, poses.size(),
        status_json.str().c_str(), json_list(wall[1]).c_str(), json_list(wall[2]).c_str(),
        json_list(cpu[1]).c_str(), json_list(cpu[2]).c_str(), json_list(steal[1]).c_str(),
        json_list(steal[2]).c_str(), make_builder_s, json_list(build_s).c_str(),
        json_list(solve_s).c_str());
    std::fflush(stdout);
  }

  // The pairs: whole sweep() calls on one thread, the two cases in turn; wall and CPU time, as
  // on a machine shared with others' work the CPU time is the steadier of the two.
  options.threads = 1;
  for (const Pair& pair : kPairs) {
    std::vector<Case> both;
    for (const Case& c : cases())
      if (c.key == pair.first || c.key == pair.second) both.push_back(c);
    std::map<std::string, std::vector<double>> wall, cpu;
    std::size_t pose_count = 0;
    for (int r = 0; r < repeats; ++r)
      for (const Case& c : both) {
        const stiffmsa::ModelFamily family =
            stiffmsa::load_model_family(std::string(STIFFMSA_EXAMPLES_DIR) + "/" + c.file);
        const stiffmsa::PoseTable poses = stiffmsa::grid_poses(c.grid);
        pose_count = poses.size();
        const double cpu_before = process_cpu_seconds();
        const auto start = Clock::now();
        (void)stiffmsa::sweep(family, poses, options);
        wall[c.key].push_back(seconds_since(start));
        cpu[c.key].push_back(process_cpu_seconds() - cpu_before);
      }
    std::printf(
        "{\"pair\": [\"%s\", \"%s\"], \"solver\": \"%s\", \"poses\": %zu, \"wall_s_first\": %s, "
        "\"wall_s_second\": %s, \"cpu_s_first\": %s, \"cpu_s_second\": %s}\n",
        pair.first.c_str(), pair.second.c_str(), stiffmsa::to_string(options.solve.solver),
        pose_count, json_list(wall[pair.first]).c_str(), json_list(wall[pair.second]).c_str(),
        json_list(cpu[pair.first]).c_str(), json_list(cpu[pair.second]).c_str());
    std::fflush(stdout);
  }
  return 0;
}
