#pragma once
// The one place a chain template becomes plain passes: a pure function of the written chain and
// the scene's light names, with no knowledge of any pass type (the template's own strings name
// the passes). The planner calls it first, so every later stage sees only plain nodes.
#include "framework/Diagnostics.h"
#include "framework/GraphDesc.h"

#include <string>
#include <vector>

namespace fp {

/// What one template became, for `framepass plan`.
struct ExpandedTemplate {
    std::string pointer;
    std::vector<std::string> lights;  //!< identifiers, in the scene's order
    std::vector<std::string> passes;  //!< names of the passes it added
};

/// Returns `graph` with every light template replaced by its passes, one copy per light in
/// `lightNames` order, each light adding into the colour the previous one produced. With no
/// lights a template adds nothing and changes nothing. Problems (an unknown placeholder, a rewire
/// of a pass or port that does not exist) are reported in `diag` at the template's pointer.
GraphDesc expandLightTemplates(const GraphDesc& graph,
                               const std::vector<std::string>& lightNames,
                               Diagnostics& diag,
                               std::vector<ExpandedTemplate>* expanded = nullptr);

}  // namespace fp
