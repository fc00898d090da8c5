#pragma once
// Pass types are registered in one explicit list (passes/BuiltinPasses.cpp), like pbrt's name
// dispatch: greppable, and immune to the linker dropping self-registering objects.
#include "framework/Diagnostics.h"
#include "framework/Params.h"
#include "framework/Pass.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace fp {

struct PassType {
    std::string id;   //!< lower_snake type id used in configs
    std::string doc;  //!< one line
    std::vector<ParamInfo> params;
    /// What the pass declares of itself for the error tools (PassRoles), at default parameters.
    PassRoles roles;
    /// Parses parameters (errors into diag under pointer) and creates the pass; returns the
    /// resolved parameter values through `resolved`.
    std::function<std::unique_ptr<Pass>(const nlohmann::json& params,
                                        const std::string& pointer,
                                        Diagnostics& diag,
                                        nlohmann::json& resolved)>
        create;
};

/// An Unreal cvar framepass knows but does not emulate (no parameter declares it).
struct RecognisedCvar {
    std::string cvar;
    nlohmann::json emulatedValue;  //!< the value framepass's chain behaves as; null = none
    std::string note;
};

class PassRegistry {
public:
    /// Registers pass class P, which provides `P::Params`, `static ParamSpec<Params> paramSpec()`
    /// and a constructor taking `const Params&`.
    template <class P>
    void add(std::string id, std::string doc) {
        PassType t;
        t.id = std::move(id);
        t.doc = std::move(doc);
        t.params = P::paramSpec().infos();
        t.roles = P(typename P::Params{}).describe().roles;
        t.create = [](const nlohmann::json& params, const std::string& pointer, Diagnostics& diag,
                      nlohmann::json& resolved) -> std::unique_ptr<Pass> {
            const auto spec = P::paramSpec();
            typename P::Params p = spec.parse(params, pointer, diag);
            resolved = spec.toJson(p);
            return std::make_unique<P>(p);
        };
        mTypes.push_back(std::move(t));
    }

    /// Declares a cvar that no parameter emulates, with the value framepass runs.
    void recognise(std::string cvar, nlohmann::json emulatedValue, std::string note) {
        mRecognised.push_back({std::move(cvar), std::move(emulatedValue), std::move(note)});
    }

    const PassType* find(const std::string& id) const;
    std::vector<std::string> ids() const;
    const std::vector<PassType>& types() const { return mTypes; }
    const std::vector<RecognisedCvar>& recognisedCvars() const { return mRecognised; }

private:
    std::vector<PassType> mTypes;
    std::vector<RecognisedCvar> mRecognised;
};

/// The registry with every built-in pass (defined in passes/BuiltinPasses.cpp).
const PassRegistry& builtinPasses();

}  // namespace fp
