// framepass completion bash: a bash completion script made from the command line itself (its
// subcommands and options as CLI11 holds them) and from the pass registry (pass types, their
// parameters and ports, the cvars they answer to), so it never falls behind the code. The build
// writes it to framepass.bash and `cmake --install` puts it where bash-completion looks.
#include "cli/Commands.h"
#include "io/CaptureProfile.h"
#include "framework/CvarTable.h"
#include "framework/Diagnostics.h"
#include "framework/PassRegistry.h"

#include <fmt/ranges.h>

#include <iostream>
#include <set>

namespace fp::cli {

namespace {

std::vector<std::string> optionNames(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app.get_options()) {
        for (const auto& l : o->get_lnames())
            names.push_back("--" + l);
        for (const auto& s : o->get_snames())
            names.push_back("-" + s);
    }
    return names;
}

std::string script(const CLI::App& app) {
    std::vector<std::string> commands;
    std::string perCommand;
    for (const CLI::App* sub : app.get_subcommands({})) {
        commands.push_back(sub->get_name());
        perCommand += fmt::format("        {}) opts=\"{}\" ;;\n", sub->get_name(),
                                  fmt::join(optionNames(*sub), " "));
    }
    std::set<std::string> params, ports, types;
    for (const auto& id : builtinPasses().ids()) {
        const PassType* t = builtinPasses().find(id);
        types.insert(id);
        for (const auto& p : t->params)
            params.insert(id + "." + p.name + "=");
        Diagnostics diag;
        nlohmann::json resolved;
        for (const auto& o :
             t->create(nlohmann::json::object(), "", diag, resolved)->describe().outputs)
            ports.insert(id + "." + o.name);
    }
    std::set<std::string> cvars;
    for (const auto& c : CvarTable(builtinPasses()).names())
        cvars.insert(c + "=");
    return fmt::format(
        R"(# bash completion for framepass (written by `framepass completion bash`)
_framepass() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}" prev="${{COMP_WORDS[COMP_CWORD-1]}}"
    local commands="{commands}" global="{global}" cmd="" i opts=""
    for ((i = 1; i < COMP_CWORD; i++)); do
        case "${{COMP_WORDS[i]}}" in
            --threads) ((i++)) ;;
            -*) ;;
            *) cmd="${{COMP_WORDS[i]}}"; break ;;
        esac
    done
    compopt +o nospace 2>/dev/null
    case "$prev" in
        --cvar) COMPREPLY=($(compgen -W "{cvars}" -- "$cur")); compopt -o nospace 2>/dev/null; return ;;
        --set) COMPREPLY=($(compgen -W "{params}" -- "$cur")); compopt -o nospace 2>/dev/null; return ;;
        --dump) COMPREPLY=($(compgen -W "all {ports}" -- "$cur")); return ;;
        --profile|--ref-profile) COMPREPLY=($(compgen -W "{profiles}" -- "$cur") $(compgen -f -X '!*.json' -- "$cur")); return ;;
        --device) COMPREPLY=($(compgen -W "cpu cuda" -- "$cur")); return ;;
        --mask) COMPREPLY=($(compgen -W "sky none shading-model= id=" -- "$cur") $(compgen -f -- "$cur")); return ;;
    esac
    if [[ -z "$cmd" ]]; then
        COMPREPLY=($(compgen -W "$commands $global" -- "$cur")); return
    fi
    case "$cmd" in
{perCommand}    esac
    if [[ "$cur" == -* ]]; then
        COMPREPLY=($(compgen -W "$opts $global" -- "$cur"))
    elif [[ "$cmd" == passes ]]; then
        COMPREPLY=($(compgen -W "{types}" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}}
complete -o filenames -F _framepass framepass
)",
        fmt::arg("commands", fmt::join(commands, " ")),
        fmt::arg("global", fmt::join(optionNames(app), " ")),
        fmt::arg("cvars", fmt::join(cvars, " ")), fmt::arg("params", fmt::join(params, " ")),
        fmt::arg("ports", fmt::join(ports, " ")),
        fmt::arg("profiles", fmt::join(io::CaptureProfile::builtinNames(), " ")),
        fmt::arg("types", fmt::join(types, " ")), fmt::arg("perCommand", perCommand));
}

}  // namespace

Command addCompletionCommand(CLI::App& app) {
    auto shell = std::make_shared<std::string>();
    CLI::App* sub =
        app.add_subcommand("completion",
                           "print a shell completion script: framepass completion bash > "
                           "/etc/bash_completion.d/framepass (cmake --install puts it in place)");
    sub->add_option("shell", *shell, "the shell (bash)")
        ->required()
        ->check(CLI::IsMember({"bash"}));
    return [&app]() {
        std::cout << script(app);
        return 0;
    };
}

}  // namespace fp::cli
