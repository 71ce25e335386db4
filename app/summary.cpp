#include "summary.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

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
                        const Mat6& matrix, const Labels& row_labels,
                        const Labels& column_labels) {
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

void print_principal_stiffness(std::ostream& out, const Mat6& compliance) {
  const PrincipalStiffness principal = principal_stiffness(compliance);
  // Padded by hand: "·" takes two bytes but one column.
  out << "  Principal stiffness (ascending)\n"
      << "    against a force  [N/m]:    " << stiffness_values(principal.translational) << '\n'
      << "    against a moment [N·m/rad]:" << stiffness_values(principal.rotational) << '\n';
}

void print_deflection(std::ostream& out, const std::optional<Vec6>& deflection, const std::string& under = "the loads") {
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
  } else if (e.compliance) {
    out << "  Stiffness: unbounded (the end effector is held rigidly in some direction)\n";
  } else {
    out << "  Stiffness: undetermined\n";
  }

  if (e.compliance) print_principal_stiffness(out, *e.compliance);
  print_deflection(out, e.deflection, e.deflection_gravity ? "the loads and self-weight" : "the loads");
  if (e.deflection_gravity) print_deflection(out, e.deflection_gravity, "self-weight alone");
  if (e.in_own_axes) print_deflection(out, e.in_own_axes->deflection, "the same loads, in the end effector's own axes");
}

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

void print_largest(std::ostream& out, const std::string& title, const Largest& largest) {
  out << title;
  if (largest.determined == 0 && largest.undetermined == 0) {
    out << ": none\n";
    return;
  }
  if (largest.determined == 0) {
    out << ": undetermined\n";
    return;
  }
  out << '\n'
      << "  force:  " << scientific(largest.force, number_width) << " N    at " << largest.force_at
      << '\n'
      << "  moment: " << scientific(largest.moment, number_width) << " N·m  at "
      << largest.moment_at << '\n';
  if (largest.undetermined > 0) {
    out << "  (and " << largest.undetermined << " undetermined)\n";
  }
}

void print_report(std::ostream& out, const SolveReport& report) {
  out << "\nSolve report" << (report.solver.empty() ? "" : " (solver " + report.solver + ")")
      << '\n'
      << "  relative residual:    " << scientific(report.relative_residual, 0, 2) << '\n'
      << "  equilibrium error:    " << scientific(report.equilibrium_error, 0, 2) << '\n'
      << "  reciprocal condition: ";
  if (report.solver == "tree")
    out << "not estimated (the tree solve factorises nothing)";
  else if (report.solver == "tree_with_cuts")
    out << "not estimated (the tree solve with cuts factorises no sparse system)";
  else
    out << scientific(report.reciprocal_condition, 0, 2);
  if (report.solver == "frame") out << " of the condensed stiffness";
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

}  // namespace

void print_solve_summary(std::ostream& out, const Result& result,
                         const std::optional<std::filesystem::path>& result_file) {
  out << "Model: " << result.model << '\n';
  print_system_size(out, result.system);

  if (result.end_effectors.empty()) out << "\nNo end effectors.\n";
  for (const EndEffectorResult& e : result.end_effectors) print_end_effector(out, e);

  Largest joint_wrench;
  for (const JointResult& joint : result.joints) joint_wrench.consider(joint.name, joint.wrench);
  out << '\n';
  print_largest(out, "Largest joint wrench (on the first link end)", joint_wrench);

  Largest support_reaction;
  for (const SupportResult& support : result.supports) {
    support_reaction.consider(support.name, support.reaction);
  }
  print_largest(out, "Largest support reaction", support_reaction);

  print_report(out, result.report);
  if (result_file) out << "\nResult written to " << result_file->string() << '\n';
}

void print_check_summary(std::ostream& out, const std::string& model_name, const SystemSize& size) {
  out << "Model: " << model_name << " is valid\n";
  print_system_size(out, size);
}

void print_error(std::ostream& err, std::string_view message) {
  err << error_prefix << message << '\n';
}

void print_input_error(std::ostream& err, const InputError& error) {
  if (error.diagnostics().empty()) {
    print_error(err, error.what());
    return;
  }
  for (const Diagnostic& diagnostic : error.diagnostics()) print_error(err, diagnostic.to_string());
}

void print_singular_model_error(std::ostream& err, const SingularModelError& error) {
  print_error(err, error.what());
  for (const std::string& detail : error.details()) err << "  " << detail << '\n';
}

}  // namespace stiffmsa::cli
