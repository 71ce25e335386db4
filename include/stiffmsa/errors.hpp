#pragma once
// Typed errors. The library never prints or exits: every failure is one of these, carrying the
// user's names and, for model files, the place in the file.
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace stiffmsa {

struct SourceLocation {
  std::string file;  // empty when the model was built through the API
  int line = 0;      // 1-based; 0 when unknown
  int column = 0;    // 1-based; 0 when unknown
};

// One defect in the user's input: where it is, which key, and what would be valid.
struct Diagnostic {
  SourceLocation location;
  std::string key_path;  // e.g. "joints.J3.axis"
  std::string message;

  // "file.yaml:12:5: joints.J3.axis: ..." (parts that are unknown are left out).
  std::string to_string() const;
};

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The model (file or API input) is invalid; every defect found is listed.
class InputError : public Error {
 public:
  explicit InputError(std::vector<Diagnostic> diagnostics);
  // A single defect.
  InputError(SourceLocation location, std::string key_path, std::string message);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

// The model is valid but cannot be solved: it is a mechanism, or numerically singular. what()
// is the summary followed by the details, one per line indented by two spaces: the whole
// story, for a caller that prints only what().
class SingularModelError : public Error {
 public:
  enum class Cause {
    free_motion,  // the structure can move without load (details name the motions)
    numerical,    // singular to working precision, with no free motion identified
  };
  SingularModelError(Cause cause, std::string summary, std::vector<std::string> details);
  Cause cause() const { return cause_; }
  // The first line of what(): a sentence saying what is wrong.
  const std::string& summary() const { return summary_; }
  // What moves and what lets it (the culprits), and how to stop it.
  const std::vector<std::string>& details() const { return details_; }

 private:
  Cause cause_;
  std::string summary_;
  std::vector<std::string> details_;
};

// The loaded mode found no equilibrium: Newton's iterations did not converge however small the
// load step, or the load path passed a limit point or a bifurcation (the tangent turned
// singular). load_factor() is the last load factor reached in equilibrium; what() says which
// case it is and where.
class NoEquilibriumError : public Error {
 public:
  NoEquilibriumError(std::string message, double load_factor)
      : Error(std::move(message)), load_factor_(load_factor) {}
  double load_factor() const { return load_factor_; }

 private:
  double load_factor_;
};

// Reading or writing a file failed (not a defect of the model's content).
class IoError : public Error {
 public:
  using Error::Error;
};

// Invalid options or API misuse (e.g. a solver not built in).
class UsageError : public Error {
 public:
  using Error::Error;
};

// A name looked up through the API (a result's end effector, a model's material) that is not
// there: what() names it, what kind of thing it was to be, and the nearest name there is
// when one is near enough to be a typo.
class NameError : public UsageError {
 public:
  // `kind` as a message names it ("end effector", "material"); `candidates`: the names there
  // are, for the suggestion or, where none is near, the list.
  NameError(std::string kind, std::string name, const std::vector<std::string>& candidates);
  const std::string& kind() const { return kind_; }
  const std::string& name() const { return name_; }
  const std::optional<std::string>& suggestion() const { return suggestion_; }

 protected:
  // The same with `message` as what(), in place of the one made from the names: a message that
  // also says where the name was looked up (a family's parameters). A copy as a NameError, a
  // catch by value, keeps it.
  NameError(std::string kind, std::string name, const std::vector<std::string>& candidates,
            std::string message);

 private:
  std::string kind_;
  std::string name_;
  std::optional<std::string> suggestion_;
};

}  // namespace stiffmsa
