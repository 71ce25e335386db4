#include "elements/element_block.hpp"

#include "stiffmsa/errors.hpp"

namespace stiffmsa::detail {

void ElementBlock::add_external_wrench(Index, int, const Vec6&, VecX&) const {
  throw Error("internal error: an external wrench was routed to a block that holds no link end");
}

}  // namespace stiffmsa::detail
