#pragma once
// A NameError whose message says where the name was looked up (a model file's or a family's
// parameters), where NameError's own says only what is missing. The message is NameError's
// what(), so that a copy as a NameError keeps it.
#include <string>
#include <utility>
#include <vector>

#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

class NameErrorInContext : public NameError {
 public:
  NameErrorInContext(std::string kind, std::string name, const std::vector<std::string>& candidates,
                     std::string message)
      : NameError(std::move(kind), std::move(name), candidates, std::move(message)) {}
};

}  // namespace stiffmsa::detail
