#include "summary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace stiffmsa::cli {
namespace {

constexpr const char* error_prefix = "stiffmsa: error: ";

// Every number in the same width, so that matrix columns line up.
constexpr int number_width = 13;

std::string scientific(double value, int width = 0, int digits = 5) {
  char buffer[64];
  // Adding +0.0 turns a negative zero (an artefact of inverting) into a plain zero.
  std::snprintf(buffer, sizeof buffer, "%*.*e", width, digits, value + 0.0);
  return buffer;
}

std::string pad_left(const std::string& text, int width) {
  const auto missing = static_cast<std::size_t>(width) > text.size()
                           ? static_cast<std::size_t>(width) - text.size()
                           : 0;
  return std::string(missing, ' ') + text;
}

using Labels = std::array<const char*, 6>;
constexpr Labels deflection_labels = {"dx", "dy", "dz", "rx", "ry", "rz"};
constexpr Labels wrench_labels = {"Fx", "Fy", "Fz", "Mx", "My", "Mz"};

// In a symmetric positive semi-definite matrix |m_ij| <= sqrt(m_ii·m_jj), whatever the units;
// an entry below 1e-12 of that bound is round-off and shown as zero. The result file keeps it.
Mat6 without_round_off(const Mat6& m) {
  constexpr double round_off = 1e-12;
  Mat6 shown = m;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      if (std::abs(m(r, c)) < round_off * std::sqrt(std::abs(m(r, r) * m(c, c)))) shown(r, c) = 0;
    }
  }
  return shown;
}

// A 6×6 matrix split into its four 3×3 blocks (translation | rotation), with row and column
// labels, under a title and a line giving the unit of each block.
void print_block_matrix(std::ostream& out, const std::string& title, const std::string& units,
                        const Mat6& matrix, const Labels& row_labels, const Labels& column_labels) {
  const Mat6 m = without_round_off(matrix);
  const std::string indent = "    ";
  const std::string block_separator = "  |";
  out << "  " << title << '\n' << indent << "units by block: " << units << '\n';

  out << indent << "  ";
  for (int c = 0; c < 6; ++c) {
    if (c == 3) out << block_separator;
    out << pad_left(column_labels[static_cast<std::size_t>(c)], number_width);
  }
  out << '\n';

  for (int r = 0; r < 6; ++r) {
    if (r == 3) {
      out << indent << std::string(2 + 3 * number_width, '-') << "--+"
          << std::string(3 * number_width, '-') << '\n';
    }
    out << indent << row_labels[static_cast<std::size_t>(r)];
    for (int c = 0; c < 6; ++c) {
      if (c == 3) out << block_separator;
      out << scientific(m(r, c), number_width);
    }
    out << '\n';
  }
}

std::string stiffness_values(const Vec3& values) {
  std::string text;
  for (int i = 0; i < 3; ++i) {
    text += "  ";
    text += std::isinf(values[i]) ? pad_left("unbounded", number_width)
                                  : scientific(values[i], number_width);
  }
  return text;
}

// A unit direction with four decimals; a component that rounds to zero is written 0.0000.
std::string direction_text(const Vec3& u) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "(%7.4f, %7.4f, %7.4f)", std::abs(u(0)) < 5e-5 ? 0.0 : u(0),
                std::abs(u(1)) < 5e-5 ? 0.0 : u(1), std::abs(u(2)) < 5e-5 ? 0.0 : u(2));
  return buffer;
}

std::string directions_text(const Mat3& directions) {
  std::string text;
  for (int i = 0; i < 3; ++i) text += "  " + direction_text(directions.col(i));
  return text;
}

void print_principal_stiffness(std::ostream& out, const Mat6& compliance) {
  const PrincipalStiffness principal = principal_stiffness(compliance);
  // Padded by hand: "·" takes two bytes but one column.
  out << "  Principal stiffness (ascending)\n"
      << "    against a force  [N/m]:    " << stiffness_values(principal.translational) << '\n'
      << "    against a moment [N·m/rad]:" << stiffness_values(principal.rotational) << '\n'
      << "  Principal directions (unit vectors in global x, y, z; in the order of the values "
         "above)\n"
      << "    of the force stiffness: " << directions_text(principal.translational_directions)
      << '\n'
      << "    of the moment stiffness:" << directions_text(principal.rotational_directions) << '\n';
}

std::string stiffness_or_unbounded(double value) {
  return std::isinf(value) ? std::string("unbounded") : scientific(value);
}

void print_directional_stiffness(std::ostream& out, const DirectionalStiffness& along) {
  out << "  Stiffness along " << direction_text(along.direction) << '\n'
      << "    against a force along it  [N/m]:     " << stiffness_or_unbounded(along.translational)
      << '\n'
      << "    against a moment about it [N·m/rad]: " << stiffness_or_unbounded(along.rotational)
      << '\n';
}

void print_deflection(std::ostream& out, const std::optional<Vec6>& deflection,
                      const std::string& under = "the loads") {
  if (!deflection) {
    out << "  Deflection under " << under << ": undetermined\n";
    return;
  }
  const Vec6& d = *deflection;
  out << "  Deflection under " << under << "\n";
  out << "    translation dx dy dz [m]:  ";
  for (int i = 0; i < 3; ++i) out << scientific(d[i], number_width);
  out << "   magnitude " << scientific(d.head<3>().norm()) << " m\n";
  out << "    rotation rx ry rz [rad]:   ";
  for (int i = 3; i < 6; ++i) out << scientific(d[i], number_width);
  out << "   magnitude " << scientific(d.tail<3>().norm()) << " rad\n";
}

// The stiffness on the directions an end effector can move in, where others are held rigidly:
// a direction that is a coordinate axis is labelled by it (dx and Fx, ...), any other d1, d2, ...
void print_reduced_stiffness(std::ostream& out, const ReducedStiffness& reduced) {
  const Eigen::Index count = reduced.matrix.rows();
  std::vector<std::string> motion(static_cast<std::size_t>(count)), wrench(motion.size());
  bool all_axes = true;
  for (Eigen::Index k = 0; k < count; ++k) {
    Eigen::Index axis = 0;
    const double largest = reduced.directions.row(k).cwiseAbs().maxCoeff(&axis);
    // The library writes a direction along a coordinate axis exactly.
    const bool on_axis = largest == 1.0 && reduced.directions.row(k).cwiseAbs().sum() == 1.0;
    all_axes &= on_axis;
    // Appended, not "d" + number: GCC 12 warns falsely (-Wrestrict) on that sum.
    std::string numbered = "d";
    numbered += std::to_string(k + 1);
    motion[static_cast<std::size_t>(k)] =
        on_axis ? deflection_labels[static_cast<std::size_t>(axis)] : numbered;
    wrench[static_cast<std::size_t>(k)] =
        on_axis ? wrench_labels[static_cast<std::size_t>(axis)] : numbered;
  }
  const std::string indent = "    ";
  out << "  Stiffness on the " << count << " directions not held rigidly (reduced_stiffness)\n";
  if (!all_axes) {
    out << indent << "directions (unit motions, [m] and [rad]):\n" << indent << "  ";
    for (const char* label : deflection_labels) out << pad_left(label, number_width);
    out << '\n';
    for (Eigen::Index k = 0; k < count; ++k) {
      out << indent << pad_left(motion[static_cast<std::size_t>(k)], 2);
      for (int c = 0; c < 6; ++c) out << scientific(reduced.directions(k, c), number_width);
      out << '\n';
    }
  }
  out << indent
      << "units as in the stiffness: N/m, N/rad in force rows; N·m/m, N·m/rad in moment rows"
      << (all_axes ? "" : " (mixed along a direction that both moves and turns)") << '\n'
      << indent << "  ";
  for (const auto& label : motion) out << pad_left(label, number_width);
  out << '\n';
  for (Eigen::Index r = 0; r < count; ++r) {
    out << indent << pad_left(wrench[static_cast<std::size_t>(r)], 2);
    for (Eigen::Index c = 0; c < count; ++c) out << scientific(reduced.matrix(r, c), number_width);
    out << '\n';
  }
}

void print_end_effector(std::ostream& out, const EndEffectorResult& e) {
  out << "\nEnd effector " << e.name << " (point " << e.point << ", link " << e.link << ", end "
      << to_string(e.end) << ")\n";

  if (e.compliance) {
    print_block_matrix(out, "Compliance: deflection per unit wrench applied at " + e.name,
                       "m/N, m/(N·m) in the translation rows; "
                       "rad/N, rad/(N·m) in the rotation rows",
                       *e.compliance, deflection_labels, wrench_labels);
  } else {
    out << "  Compliance: undetermined (the structure can move freely)\n";
  }

  if (e.stiffness) {
    print_block_matrix(out, "Stiffness: wrench at " + e.name + " per unit deflection there",
                       "N/m, N/rad in the force rows; N·m/m, N·m/rad in the moment rows",
                       *e.stiffness, wrench_labels, deflection_labels);
    if (e.stiffness_asymmetry)
      out << "  Stiffness asymmetry: " << scientific(*e.stiffness_asymmetry, 0, 2)
          << " (|K - K^T| / |K + K^T|, rotations weighted by the model size; under load "
             "the tangent stiffness need not be symmetric)\n";
  } else if (e.compliance) {
    out << "  Stiffness: unbounded (the end effector is held rigidly in some direction)\n";
    if (e.reduced_stiffness) print_reduced_stiffness(out, *e.reduced_stiffness);
  } else {
    out << "  Stiffness: undetermined\n";
  }

  if (e.compliance) print_principal_stiffness(out, *e.compliance);
  if (e.along_direction) print_directional_stiffness(out, *e.along_direction);
  print_deflection(out, e.deflection,
                   e.deflection_gravity ? "the loads and self-weight" : "the loads");
  if (e.deflection_gravity) print_deflection(out, e.deflection_gravity, "self-weight alone");
  if (e.in_own_axes)
    print_deflection(out, e.in_own_axes->deflection,
                     "the same loads, in the end effector's own axes");
}

// Below this fraction of the wrenches' scale (the largest force times the model's size, or the
// largest moment), a force or moment is round-off, not a value to report.
constexpr double kRoundOffWrench = 1e-12;

// The entries with the largest force and the largest moment (which may differ), by norm.
struct Largest {
  std::size_t determined = 0;
  std::size_t undetermined = 0;
  double force = 0;
  std::string force_at;
  double moment = 0;
  std::string moment_at;

  void consider(const std::string& name, const std::optional<Vec6>& wrench) {
    if (!wrench) {
      ++undetermined;
      return;
    }
    const double f = wrench->head<3>().norm();
    const double m = wrench->tail<3>().norm();
    if (determined == 0 || f > force) {
      force = f;
      force_at = name;
    }
    if (determined == 0 || m > moment) {
      moment = m;
      moment_at = name;
    }
    ++determined;
  }
};

void print_largest(std::ostream& out, const std::string& title, const Largest& largest,
                   double lever) {
  out << title;
  if (largest.determined == 0 && largest.undetermined == 0) {
    out << ": none\n";
    return;
  }
  if (largest.determined == 0) {
    out << ": undetermined\n";
    return;
  }
  const double scale = std::max(largest.force * lever, largest.moment);
  const auto round_off = [&](double value) { return value <= kRoundOffWrench * scale; };
  out << '\n';
  if (round_off(largest.force * lever))
    out << "  force:  none (every force is zero or round-off)\n";
  else
    out << "  force:  " << scientific(largest.force, number_width) << " N    at "
        << largest.force_at << '\n';
  if (round_off(largest.moment))
    out << "  moment: none (every moment is zero or round-off)\n";
  else
    out << "  moment: " << scientific(largest.moment, number_width) << " N·m  at "
        << largest.moment_at << '\n';
  if (largest.undetermined > 0) {
    out << "  (and " << largest.undetermined << " undetermined)\n";
  }
}

void print_report(std::ostream& out, const SolveReport& report) {
  const std::string solver = to_string(report.solver);
  out << "\nSolve report" << (solver.empty() ? "" : " (solver " + solver + ")") << '\n'
      << "  relative residual:    " << scientific(report.relative_residual, 0, 2) << '\n'
      << "  equilibrium error:    " << scientific(report.equilibrium_error, 0, 2) << '\n'
      << "  reciprocal condition: ";
  if (report.solver == SolverUsed::tree)
    out << "not estimated (the tree solve factorises nothing)";
  else if (report.solver == SolverUsed::tree_with_cuts)
    out << "not estimated (the tree solve with cuts factorises no sparse system)";
  else if (report.reciprocal_condition == 0)
    out << "0 (the system is singular: it was solved with its free motions or redundant "
           "constraints removed)";
  else
    out << scientific(report.reciprocal_condition, 0, 2);
  if (report.solver == SolverUsed::frame) out << " of the condensed stiffness";
  if (report.reciprocal_condition > 0) {
    out << "  (condition number about " << scientific(1.0 / report.reciprocal_condition, 0, 1)
        << ')';
  }
  out << '\n';
  for (const std::string& note : report.notes) out << "  note: " << note << '\n';
  for (const std::string& warning : report.warnings) out << "  warning: " << warning << '\n';
}

void print_system_size(std::ostream& out, const SystemSize& size) {
  out << "System: " << size.unknowns << " unknowns, " << size.equations << " equations, "
      << size.nonzeros << " non-zeros\n";
}

// "(0, 0, 1)", the numbers as the user would write them.
std::string vector_text(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x() + 0.0, v.y() + 0.0, v.z() + 0.0);
  return buffer;
}

std::string pad_right(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : text + std::string(width - text.size(), ' ');
}

const char* link_kind_name(const LinkKind& kind) {
  constexpr std::array<const char*, 4> names = {"beam", "rigid", "matrix", "compliance"};
  return names[kind.index()];
}

// What a joint or support does along its free directions, and the axes it is given.
std::string connection_text(const Connection& c) {
  const Kinematics& k = c.kinematics;
  std::string text = to_string(k.type);
  text += c.is_actuated                ? ", actuated"
          : c.stiffness                ? ", elastic"
          : k.type == JointType::rigid ? ""
                                       : ", passive";
  switch (k.type) {
    case JointType::revolute:
    case JointType::prismatic:
    case JointType::cylindrical: text += ", axis " + vector_text(k.axis); break;
    case JointType::universal:
      text += ", axes " + vector_text(k.axis) + " and " + vector_text(k.axis_b);
      break;
    case JointType::planar: text += ", normal " + vector_text(k.normal); break;
    default: break;
  }
  return text;
}

// Each link's length and each joint's and support's axes, in the user's names: a link in the
// wrong place, an axis typed wrong or millimetres for metres show without a solve.
void print_geometry(std::ostream& out, const Model& model) {
  std::size_t width = 4;
  for (const Link& link : model.links) width = std::max(width, link.name.size());
  for (const Joint& joint : model.joints) width = std::max(width, joint.name.size());
  for (const Support& support : model.supports) width = std::max(width, support.name.size());
  width = std::min<std::size_t>(width, 24) + 2;
  std::unordered_map<std::string_view, const Point*>
      points;  // a 100 000-link chain, looked up once each
  for (const Point& point : model.points) points.emplace(point.name, &point);
  const auto find = [&](const std::string& name) -> const Point* {
    const auto found = points.find(name);
    return found == points.end() ? nullptr : found->second;
  };
  if (!model.links.empty()) out << "\nLinks (length in m):\n";
  for (const Link& link : model.links) {
    const Point* from = find(link.from);
    const Point* to = find(link.to);
    const double length = from && to ? (to->position - from->position).norm() : 0.0;
    char number[32];
    std::snprintf(number, sizeof number, "%.6g", length);
    out << "  " << pad_right(link.name, width) << pad_right(link_kind_name(link.kind), 12)
        << pad_right(number, 13) << link.from << " -> " << link.to << '\n';
  }
  if (!model.joints.empty()) out << "\nJoints:\n";
  for (const Joint& joint : model.joints)
    out << "  " << pad_right(joint.name, width) << "at " << joint.at << ": "
        << connection_text(joint.connection) << '\n';
  if (!model.supports.empty()) out << "\nSupports:\n";
  for (const Support& support : model.supports)
    out << "  " << pad_right(support.name, width) << "at " << support.at << ": "
        << connection_text(support.connection) << '\n';
}

}  // namespace

// "12.5 times the loads (link 'column' bends …)", or that none buckles; a line.
std::string critical_load_text(const CriticalLoad& critical) {
  if (!critical.factor) return "none (no multiple of the loads buckles the structure)\n";
  char factor[32];
  std::snprintf(factor, sizeof factor, "%.6g", *critical.factor);
  return std::string(factor) + " times the loads" +
         (critical.mode.empty() ? "" : " (" + critical.mode + ")") + '\n';
}

// A named load case, short: each end effector's deflection, the largest joint wrench and support
// reaction, its equilibrium check and what it warns of beyond the top level's warnings.
void print_load_case(std::ostream& out, const Result& c, const Result& top) {
  out << "\nLoad case " << c.load_case << '\n';
  for (const EndEffectorResult& e : c.end_effectors) {
    out << " End effector " << e.name << '\n';
    print_deflection(out, e.deflection);
  }
  Largest joint_wrench, support_reaction;
  for (const JointResult& joint : c.joints) joint_wrench.consider(joint.name, joint.wrench);
  for (const SupportResult& support : c.supports)
    support_reaction.consider(support.name, support.reaction);
  print_largest(out, "Largest joint wrench (on the first link end)", joint_wrench, c.model_size);
  print_largest(out, "Largest support reaction", support_reaction, c.model_size);
  out << "  equilibrium error: " << scientific(c.report.equilibrium_error, 0, 2) << '\n';
  if (c.critical_load) out << "  critical load factor: " << critical_load_text(*c.critical_load);
  for (const std::string& warning : c.report.warnings)
    if (std::find(top.report.warnings.begin(), top.report.warnings.end(), warning) ==
        top.report.warnings.end())
      out << "  warning: " << warning << '\n';
}

void print_solve_summary(std::ostream& out, const Result& result,
                         const std::optional<std::filesystem::path>& result_file) {
  out << "Model: " << result.model << '\n';
  if (!result.parameters.empty())
    out << "Parameters: " << parameters_text(result.parameters) << '\n';
  if (!result.load_cases.empty())
    out << "Load case: "
        << (result.load_case.empty() ? "the unnamed one (loads:)" : result.load_case) << " below; "
        << result.load_cases.size()
        << (result.load_cases.size() == 1 ? " named case" : " named cases") << " after it\n";
  print_system_size(out, result.system);
  if (result.analysis.mode == AnalysisMode::loaded)
    out << "Analysis: loaded (equilibrium in the deformed geometry) in "
        << result.analysis.load_steps
        << (result.analysis.load_steps == 1 ? " load step, " : " load steps, ")
        << result.analysis.iterations
        << " Newton iterations; compliance and stiffness are the tangent ones there\n";

  if (result.end_effectors.empty()) out << "\nNo end effectors.\n";
  for (const EndEffectorResult& e : result.end_effectors) print_end_effector(out, e);

  Largest joint_wrench;
  for (const JointResult& joint : result.joints) joint_wrench.consider(joint.name, joint.wrench);
  out << '\n';
  print_largest(out, "Largest joint wrench (on the first link end)", joint_wrench,
                result.model_size);

  Largest support_reaction;
  for (const SupportResult& support : result.supports) {
    support_reaction.consider(support.name, support.reaction);
  }
  print_largest(out, "Largest support reaction", support_reaction, result.model_size);

  if (result.critical_load)
    out << "\nCritical load factor: " << critical_load_text(*result.critical_load);
  print_report(out, result.report);
  for (const Result& c : result.load_cases) print_load_case(out, c, result);
  if (result_file) out << "\nResult written to " << result_file->string() << '\n';
}

void print_check_summary(std::ostream& out, const Model& model, const SystemSize& size,
                         const std::vector<Diagnostic>& warnings) {
  out << "Model: " << model.name << " is valid\n";
  print_system_size(out, size);
  for (const Diagnostic& warning : warnings) out << "  warning: " << warning.to_string() << '\n';
  print_geometry(out, model);
}

std::string value_with_unit(double value, const std::string& unit) {
  return unit.empty() ? shortest_text(value) : shortest_text(value) + " " + unit;
}

std::string parameters_text(const std::vector<ParameterValue>& parameters) {
  std::string text;
  for (const ParameterValue& p : parameters)
    text += (text.empty() ? "" : ", ") + p.name + " = " + value_with_unit(p.value, p.unit) +
            (p.set ? " (set)" : "");
  return text;
}

// The library's messages name its own options; on the command line they are set by flags, which
// the messages printed here name instead.
std::string with_flag_hints(std::string_view message) {
  static constexpr std::pair<std::string_view, std::string_view> kFlagOfOption[] = {
      {"(LoadLimits::max_file_bytes)", "with --max-file-size BYTES"},
      {"(LoadLimits::max_nesting_depth)", "with --max-depth N"},
      {"(LoadLimits::max_entities)", "with --max-entities N"},
      {"SolveOptions::accept_idle_motions", "--accept-idle-motions"},
      {"SweepOptions::load_case", "--case"}};
  std::string text(message);
  for (const auto& [option, flag] : kFlagOfOption)
    for (auto at = text.find(option); at != std::string::npos;
         at = text.find(option, at + flag.size()))
      text.replace(at, option.size(), flag);
  return text;
}

void print_error(std::ostream& err, std::string_view message) {
  err << error_prefix << with_flag_hints(message) << '\n';
}

void print_input_error(std::ostream& err, const InputError& error) {
  if (error.diagnostics().empty()) {
    print_error(err, error.what());
    return;
  }
  for (const Diagnostic& diagnostic : error.diagnostics()) print_error(err, diagnostic.to_string());
}

void print_singular_model_error(std::ostream& err, const SingularModelError& error) {
  // what() holds the summary and its details, one per line.
  print_error(err, error.what());
}

// Called from a catch block: turns the exception in flight into a message and an exit code.
int report_current_exception() noexcept {
  try {
    try {
      throw;
    } catch (const SingularModelError& e) {
      print_singular_model_error(std::cerr, e);
      return exit_cannot_solve;
    } catch (const NoEquilibriumError& e) {
      print_error(std::cerr, e.what());
      return exit_cannot_solve;
    } catch (const InputError& e) {
      print_input_error(std::cerr, e);
      return exit_invalid_input;
    } catch (const std::bad_alloc&) {
      print_error(std::cerr, "out of memory");
      return exit_invalid_input;
    } catch (const std::exception& e) {
      // IoError, UsageError and anything unexpected: the message says what went wrong.
      print_error(std::cerr, e.what());
      return exit_invalid_input;
    } catch (...) {
      print_error(std::cerr, "unknown internal error");
      return exit_invalid_input;
    }
  } catch (...) {
    // Even reporting failed (no memory for the message, say); the exit code still tells.
    return exit_invalid_input;
  }
}

}  // namespace stiffmsa::cli
