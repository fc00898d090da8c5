// framepass completion bash|zsh|fish: a shell completion script made from the command line itself
// (its subcommands and options as CLI11 holds them) and from the pass registry (pass types, the
// cvars they answer to), so it never falls behind the code. After --set, --input and --dump the
// scripts ask `framepass completion --names CONFIG --for KIND` for the names of the chain the
// config on the command line resolves to (a preset's pass names, light templates expanded), never
// a fixed list. The build writes the three scripts beside the executable and `cmake --install`
// puts them where the shells look.
#include "cli/Commands.h"
#include "app/Settings.h"
#include "app/RunSetup.h"
#include "io/CaptureProfile.h"
#include "foundation/Error.h"
#include "framework/CvarTable.h"
#include "framework/Diagnostics.h"
#include "framework/PassRegistry.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <iostream>
#include <optional>
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

// The options, of the app and of every subcommand, that take a value: the word after one of them
// is not the command or the config.
std::vector<std::string> valueOptions(const CLI::App& app) {
    std::set<std::string> names;
    std::vector<const CLI::App*> apps{&app};
    for (const CLI::App* sub : app.get_subcommands({})) apps.push_back(sub);
    for (const CLI::App* a : apps)
        for (const CLI::Option* o : a->get_options()) {
            if (!o->nonpositional() || o->get_items_expected_min() <= 0) continue;
            for (const auto& l : o->get_lnames()) names.insert("--" + l);
            for (const auto& s : o->get_snames()) names.insert("-" + s);
        }
    return {names.begin(), names.end()};
}

// A help line short enough for a completion menu: one line, at most ~70 characters.
std::string brief(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\t') c = ' ';
    if (text.size() <= 72) return text;
    std::size_t cut = text.rfind(' ', 70);
    if (cut == std::string::npos || cut < 30) cut = 70;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
    text.resize(cut);
    while (!text.empty() && (text.back() == ',' || text.back() == ';' || text.back() == ' '))
        text.pop_back();
    return text + "…";
}

// Text inside single quotes, for bash and zsh ('it'\''s').
std::string shQuoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// Text inside single quotes, for fish ('it\'s', '\\').
std::string fishQuoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) {
        if (c == '\'' || c == '\\') out += '\\';
        out += c;
    }
    return out + "'";
}

// The words every script offers besides the options: cvar names (with the '=' they take),
// built-in profiles, pass types.
struct Words {
    std::vector<std::string> cvars, profiles, types;
};

Words words() {
    Words w;
    for (const auto& id : builtinPasses().ids()) w.types.push_back(id);
    std::set<std::string> cvars;
    for (const auto& c : app::builtinCvarTable().names()) cvars.insert(c + "=");
    w.cvars.assign(cvars.begin(), cvars.end());
    w.profiles = io::CaptureProfile::builtinNames();
    return w;
}

std::string bashScript(const CLI::App& app) {
    const Words w = words();
    std::vector<std::string> commands;
    std::string perCommand;
    for (const CLI::App* sub : app.get_subcommands({})) {
        commands.push_back(sub->get_name());
        perCommand += fmt::format("        {}) opts=\"{}\" ;;\n", sub->get_name(),
                                  fmt::join(optionNames(*sub), " "));
    }
    return fmt::format(
        R"SH(# bash completion for framepass (written by `framepass completion bash`)
# The names after --set, --input and --dump ($1: set, input or dump): those of the chain the
# config on the command line resolves to.
_framepass_names() {{
    local fp="${{COMP_WORDS[0]}}" cfg="" i seen=""
    for ((i = 1; i < COMP_CWORD; i++)); do
        case "${{COMP_WORDS[i]}}" in
            {valueOptions}) ((i++)) ;;
            -*) ;;
            *) if [[ -n "$seen" ]]; then cfg="${{COMP_WORDS[i]}}"; break; fi; seen=1 ;;
        esac
    done
    [[ -n "$cfg" && "$cfg" != - ]] || return 0
    "${{fp/#\~/$HOME}}" -q completion --names "${{cfg/#\~/$HOME}}" --for "$1" 2>/dev/null
}}
_framepass() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}" prev="${{COMP_WORDS[COMP_CWORD-1]}}"
    local commands="{commands}" global="{global}" cmd="" i opts="" word names=()
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
        --set|--input)
            while read -r word; do names+=("$word"); done < <(_framepass_names "${{prev#--}}")
            COMPREPLY=($(compgen -W "${{names[*]}}" -- "$cur")); compopt -o nospace 2>/dev/null; return ;;
        --dump)
            while read -r word; do names+=("$word"); done < <(_framepass_names dump)
            COMPREPLY=($(compgen -W "all ${{names[*]}}" -- "$cur")); return ;;
        --profile|--ref-profile) COMPREPLY=($(compgen -W "{profiles}" -- "$cur") $(compgen -f -X '!*.json' -- "$cur")); return ;;
        --device) COMPREPLY=($(compgen -W "cpu cuda" -- "$cur")); return ;;
        --mask) COMPREPLY=($(compgen -W "sky none reflected-emitter shading-model= id=" -- "$cur") $(compgen -f -- "$cur")); return ;;
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
    elif [[ "$cmd" == schema ]]; then
        COMPREPLY=($(compgen -W "config scene" -- "$cur"))
    elif [[ "$cmd" == completion ]]; then
        COMPREPLY=($(compgen -W "bash zsh fish" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}}
complete -o filenames -F _framepass framepass
)SH",
        fmt::arg("valueOptions", fmt::join(valueOptions(app), "|")),
        fmt::arg("commands", fmt::join(commands, " ")),
        fmt::arg("global", fmt::join(optionNames(app), " ")),
        fmt::arg("cvars", fmt::join(w.cvars, " ")),
        fmt::arg("profiles", fmt::join(w.profiles, " ")),
        fmt::arg("types", fmt::join(w.types, " ")), fmt::arg("perCommand", perCommand));
}

// zsh: `_describe` entries, NAME:DESCRIPTION, one per option name.
std::string zshOptionSpecs(const CLI::App& app) {
    std::vector<std::string> specs;
    for (const CLI::Option* o : app.get_options()) {
        std::vector<std::string> names;
        for (const auto& l : o->get_lnames()) names.push_back("--" + l);
        for (const auto& s : o->get_snames()) names.push_back("-" + s);
        for (const auto& n : names)
            specs.push_back(shQuoted(n + ":" + brief(o->get_description())));
    }
    return fmt::format("{}", fmt::join(specs, " "));
}

std::string zshScript(const CLI::App& app) {
    const Words w = words();
    std::vector<std::string> commands;
    std::string perCommand;
    for (const CLI::App* sub : app.get_subcommands({})) {
        commands.push_back(shQuoted(sub->get_name() + ":" + brief(sub->get_description())));
        perCommand += fmt::format("        ({}) opts=({}) ;;\n", sub->get_name(),
                                  zshOptionSpecs(*sub));
    }
    return fmt::format(
        R"SH(#compdef framepass
# zsh completion for framepass (written by `framepass completion zsh`). Put it in a folder of
# $fpath as _framepass, or `source <(framepass completion zsh)` after compinit.

# The names after --set (PASS.PARAM=), --input (PASS.INPUT=) or --dump (PASS.PORT), $1 saying
# which: those of the chain the config on the command line resolves to, as `framepass completion
# --names CONFIG --for $1` gives them.
_framepass_names() {{
    local fp=${{(Q)words[1]}} cfg="" i seen=0
    for ((i = 2; i < CURRENT; i++)); do
        case ${{words[i]}} in
            ({valueOptions}) ((i++)) ;;
            (-*) ;;
            (*) if ((seen)); then cfg=${{(Q)words[i]}}; break; fi; seen=1 ;;
        esac
    done
    [[ -n $cfg && $cfg != - ]] || return 0
    ${{fp/#\~/$HOME}} -q completion --names ${{cfg/#\~/$HOME}} --for $1 2>/dev/null
}}

_framepass() {{
    local -a commands global opts names
    local -a cvars=({cvars})
    local -a profiles=({profiles})
    local -a types=({types})
    commands=({commands})
    global=({global})
    local cmd="" i prev=${{words[CURRENT-1]}} cur=${{words[CURRENT]}}
    for ((i = 2; i < CURRENT; i++)); do
        case ${{words[i]}} in
            (--threads) ((i++)) ;;
            (-*) ;;
            (*) cmd=${{words[i]}}; break ;;
        esac
    done
    case $prev in
        (--cvar) compadd -S '' -a cvars; return ;;
        (--set|--input) names=(${{(f)"$(_framepass_names ${{prev#--}})"}}); compadd -S '' -a names; return ;;
        (--dump) names=(all ${{(f)"$(_framepass_names dump)"}}); compadd -a names; return ;;
        (--profile|--ref-profile) compadd -a profiles; _files -g '*.json'; return ;;
        (--device) compadd cpu cuda; return ;;
        (--mask) compadd sky none reflected-emitter; compadd -S '' shading-model= id=; _files; return ;;
        (--threads) return ;;
    esac
    if [[ -z $cmd ]]; then
        if [[ $cur == -* ]]; then
            _describe -t options 'global option' global
        else
            _describe -t commands 'framepass command' commands
        fi
        return
    fi
    case $cmd in
{perCommand}    esac
    if [[ $cur == -* ]]; then
        _describe -t options "$cmd option" opts -- global
    elif [[ $cmd == passes ]]; then
        compadd -a types
    elif [[ $cmd == schema ]]; then
        compadd config scene
    elif [[ $cmd == completion ]]; then
        compadd bash zsh fish
    else
        _files
    fi
}}

if [[ $funcstack[1] == _framepass ]]; then
    _framepass "$@"
else
    compdef _framepass framepass
fi
)SH",
        fmt::arg("valueOptions", fmt::join(valueOptions(app), "|")),
        fmt::arg("cvars", fmt::join(w.cvars, " ")),
        fmt::arg("profiles", fmt::join(w.profiles, " ")),
        fmt::arg("types", fmt::join(w.types, " ")), fmt::arg("commands", fmt::join(commands, " ")),
        fmt::arg("global", zshOptionSpecs(app)), fmt::arg("perCommand", perCommand));
}

// fish: one `complete` line per option, its value's words where framepass knows them.
std::string fishOptions(const CLI::App& app, const std::string& condition, const Words& w) {
    std::string lines;
    for (const CLI::Option* o : app.get_options()) {
        if (!o->nonpositional()) continue;
        std::string line = "complete -c framepass";
        if (!condition.empty()) line += " -n " + fishQuoted(condition);
        for (const auto& s : o->get_snames()) line += " -s " + s;
        for (const auto& l : o->get_lnames()) line += " -l " + l;
        const auto& l = o->get_lnames();
        auto is = [&](const char* name) { return std::find(l.begin(), l.end(), name) != l.end(); };
        if (o->get_items_expected_min() > 0) {
            if (is("cvar"))
                line += " -x -a " + fishQuoted(fmt::format("{}", fmt::join(w.cvars, " ")));
            else if (is("set"))
                line += " -x -a '(__framepass_names set)'";
            else if (is("input"))
                line += " -x -a '(__framepass_names input)'";
            else if (is("dump"))
                line += " -x -a '(__framepass_names dump)'";
            else if (is("profile") || is("ref-profile"))
                line += " -r -a " + fishQuoted(fmt::format("{}", fmt::join(w.profiles, " ")));
            else if (is("device"))
                line += " -x -a 'cpu cuda'";
            else if (is("mask"))
                line += " -r -a 'sky none reflected-emitter shading-model= id='";
            else if (is("threads"))
                line += " -x";
            else
                line += " -r";
        }
        lines += line + " -d " + fishQuoted(brief(o->get_description())) + "\n";
    }
    return lines;
}

std::string fishScript(const CLI::App& app) {
    const Words w = words();
    std::string commands, perCommand;
    for (const CLI::App* sub : app.get_subcommands({})) {
        commands += fmt::format("complete -c framepass -n 'not __framepass_command' -f -a {} -d {}\n",
                                sub->get_name(), fishQuoted(brief(sub->get_description())));
        perCommand += fishOptions(*sub, "__framepass_using " + sub->get_name(), w);
    }
    return fmt::format(
        R"SH(# fish completion for framepass (written by `framepass completion fish`). Put it in
# ~/.config/fish/completions/framepass.fish, or `framepass completion fish | source`.

# The subcommand on the command line, if there is one yet.
function __framepass_command
    set -l skip 0
    for t in (commandline -opc)[2..-1]
        if test $skip = 1
            set skip 0
            continue
        end
        switch $t
            case --threads
                set skip 1
            case '-*'
            case '*'
                echo $t
                return 0
        end
    end
    return 1
end

function __framepass_using
    set -l cmd (__framepass_command)
    test "$cmd" = "$argv[1]"
end

# The names after --set (PASS.PARAM=), --input (PASS.INPUT=) or --dump (PASS.PORT), $argv[1]
# saying which: those of the chain the config on the command line resolves to, as `framepass
# completion --names CONFIG --for $argv[1]` gives them.
function __framepass_names
    set -l tokens (commandline -opc)
    set -l cfg
    set -l seen 0
    set -l skip 0
    for t in $tokens[2..-1]
        if test $skip = 1
            set skip 0
            continue
        end
        switch $t
            case {valueOptions}
                set skip 1
            case '-*'
            case '*'
                if test $seen = 1
                    set cfg $t
                    break
                end
                set seen 1
        end
    end
    if test -z "$cfg" -o "$cfg" = -
        return 0
    end
    test "$argv[1]" = dump; and echo all
    set -l fp (string replace -r '^~/' "$HOME/" -- $tokens[1])
    $fp -q completion --names (string replace -r '^~/' "$HOME/" -- $cfg) --for $argv[1] 2>/dev/null
end

complete -c framepass -e
{commands}complete -c framepass -n '__framepass_using passes' -f -a {types}
complete -c framepass -n '__framepass_using schema' -f -a 'config scene'
complete -c framepass -n '__framepass_using completion' -f -a 'bash zsh fish'
{global}{perCommand})SH",
        fmt::arg("valueOptions", fmt::join(valueOptions(app), " ")),
        fmt::arg("types", fishQuoted(fmt::format("{}", fmt::join(w.types, " ")))),
        fmt::arg("commands", commands), fmt::arg("global", fishOptions(app, "", w)),
        fmt::arg("perCommand", perCommand));
}

// What --set, --input and --dump take on the chain `config` resolves to (`kind`: "set", "input"
// or "dump"; empty: all three, in that order): PASS.PARAM=, PASS.INPUT= and PASS.PORT, in chain
// order. Every pass is planned (none culled), so
// a pass the outputs do not reach is there too; where that plan fails (a pass that could only
// run with inputs the config lacks), the culled passes of the ordinary plan come from their type.
std::vector<std::string> chainNames(const std::string& config, const std::string& kind) {
    SetupOptions o;
    o.config = config;
    o.allowUnknownCvars = true;
    o.runEveryPass = true;
    std::optional<RunSetup> setup;
    try {
        setup.emplace(o);
    } catch (const Error&) {
        o.runEveryPass = false;
        setup.emplace(o);
    }
    std::vector<std::string> sets, inputs, dumps;
    std::set<std::string> seen;
    auto add = [&](std::vector<std::string>& to, const std::string& word) {
        if (seen.insert(word).second) to.push_back(word);
    };
    auto addPass = [&](const std::string& name, const nlohmann::json& params, const PassIO& io) {
        for (const auto& [param, value] : params.items()) add(sets, name + "." + param + "=");
        for (const auto& in : io.inputs) add(inputs, name + "." + in.name + "=");
        for (const auto& out : io.outputs) add(dumps, name + "." + out.name);
    };
    for (const auto& s : setup->plan().steps) addPass(s.name, s.params, s.io);
    for (const auto& c : setup->plan().culled) {
        const PassType* t = builtinPasses().find(c.type);
        if (!t) continue;
        Diagnostics diag;
        nlohmann::json resolved;
        const auto pass = t->create(nlohmann::json::object(), "", diag, resolved);
        if (!pass) continue;
        addPass(c.name, resolved, pass->describe());
    }
    if (kind == "set") return sets;
    if (kind == "input") return inputs;
    if (kind == "dump") return dumps;
    sets.insert(sets.end(), inputs.begin(), inputs.end());
    sets.insert(sets.end(), dumps.begin(), dumps.end());
    return sets;
}

}  // namespace

Command addCompletionCommand(CLI::App& app) {
    auto shell = std::make_shared<std::string>();
    auto names = std::make_shared<std::string>(), kind = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand(
        "completion",
        "print a shell completion script (bash, zsh or fish): framepass completion bash > "
        "/etc/bash_completion.d/framepass (cmake --install puts all three in place)");
    CLI::Option* shellOption = sub->add_option("shell", *shell, "the shell: bash, zsh or fish")
                                   ->check(CLI::IsMember({"bash", "zsh", "fish"}));
    sub->add_option("--names", *names,
                    "instead of a script, print what --set, --input and --dump take on the chain "
                    "CONFIG resolves to, one a line: PASS.PARAM=, PASS.INPUT=, then PASS.PORT (the "
                    "scripts ask this)")
        ->type_name("CONFIG")
        ->excludes(shellOption);
    sub->add_option("--for", *kind, "with --names: only what that option takes")
        ->check(CLI::IsMember({"set", "input", "dump"}))
        ->needs(sub->get_option("--names"));
    return [&app, shell, names, kind]() {
        if (!names->empty()) {
            for (const auto& word : chainNames(*names, *kind)) std::cout << word << "\n";
            return 0;
        }
        if (shell->empty())
            throw UsageError("completion: name the shell (bash, zsh or fish), or --names CONFIG");
        std::cout << (*shell == "zsh"    ? zshScript(app)
                      : *shell == "fish" ? fishScript(app)
                                         : bashScript(app));
        return 0;
    };
}

}  // namespace fp::cli
