#pragma once
// What each Truth.* layer measures, and what each pass output that may be judged against one
// measures, declared once (TruthDefinitions.cpp) so that a measure against a truth of another
// definition says so (issue 46): rt_ambient_occlusion at Unreal's 200 cm against a Truth.AO of
// 1 m, SSGI's any-distance AO against Truth.AO, a one-bounce pass against every bounce.
//
// A definition is a few quantities, each a number:
//   radius   metres; +inf = occluders at any distance      (Truth.AO, Truth.AOAnyDistance)
//   bounces  diffuse bounces a path follows                 (Truth.DiffuseIndirect*, ...)
// `capture --truth` records them in the EXR header as string attributes
// framepass:truth.<Name>.<quantity> (radius in scene units, "inf" for any distance; docs/
// captures.md), and readTruthDefinitions gives them back.
#include "framework/Diagnostics.h"

#include <map>
#include <string>
#include <vector>

#include <OpenEXR/ImfForward.h>

namespace fp {
struct Plan;
}

namespace fp::app {

/// Quantity → value of one layer's definition ("radius" in metres, "bounces").
using TruthDefinition = std::map<std::string, double>;
/// Truth layer ("Truth.AO") → its definition, as a capture recorded it.
using TruthDefinitions = std::map<std::string, TruthDefinition>;

/// The header attributes that record the definitions of the truth layers `capture --truth`
/// writes: AO radius `aoRadius` (scene units), path bounces `maxBounces`.
std::map<std::string, std::string> truthDefinitionAttributes(double aoRadius, int maxBounces);

/// The definitions a capture's header records; empty for a capture without them. Reads
/// framepass:truthAoRadius (scene units) of captures made before the attributes above, and the
/// definitions fixed by a layer's name (Truth.AOAnyDistance, Truth.DiffuseIndirectOneBounce)
/// wherever the header records any.
TruthDefinitions readTruthDefinitions(const Imf::Header& header);

/// A warning for every error_measure of `plan` that judges a pass output against a truth layer
/// of another definition: which setting differs and which setting, truth layer or capture
/// option would match. `pointer` is the error_measure's.
std::vector<Diagnostic> truthDefinitionWarnings(const Plan& plan, const TruthDefinitions& truths);

/// compare's warnings: layer `layerA` of `nameA` and `layerB` of `nameB` were made to measure
/// different things (both definitions known, some quantity differs).
std::vector<std::string> truthDefinitionMismatch(const std::string& nameA,
                                                 const std::string& layerA,
                                                 const TruthDefinitions& a,
                                                 const std::string& nameB,
                                                 const std::string& layerB,
                                                 const TruthDefinitions& b);

}  // namespace fp::app
