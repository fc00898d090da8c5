// framepass: re-runs Unreal's deferred lighting passes on captured GBuffers.
#include "cli/Commands.h"
#include "foundation/Error.h"
#include "foundation/Limits.h"
#include "foundation/Suggest.h"
#include "io/SafeFiles.h"

#include <fmt/ranges.h>

#include <OpenEXR/ImfThreading.h>
#include <OpenImageIO/imageio.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <csignal>
#include <iostream>
#include <memory>
#include <thread>

#include <unistd.h>

namespace {
// Writes a number into `out` (async-signal-safe: no formatting library); returns the length.
int formatCount(int n, char* out) {
    char digits[12];
    int len = 0;
    do digits[len++] = char('0' + n % 10);
    while ((n /= 10) > 0 && len < 11);
    for (int i = 0; i < len; ++i) out[i] = digits[len - 1 - i];
    return len;
}

extern "C" void onStopSignal(int signal) {
    if (fp::app::stopSignal() != 0) {  // asked twice: stop now, saying so, leaving no temporary
        const int removed = fp::io::removeInFlightTemporaries();
        char line[160];
        int n = 0;
        auto put = [&](const char* text) {
            while (*text && n < int(sizeof line) - 1) line[n++] = *text++;
        };
        put("framepass: a second stop signal: stopping at once, without the safe point; ");
        n += formatCount(removed, line + n);
        put(removed == 1 ? " temporary file removed\n" : " temporary files removed\n");
        [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line, std::size_t(n));
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
    fp::app::requestStop(signal);
}
}  // namespace

void fp::cli::catchStopSignals() {
    std::signal(SIGTERM, onStopSignal);
    std::signal(SIGINT, onStopSignal);
}

int main(int argc, char** argv) {
    CLI::App app{"framepass — re-run Unreal's screen-space and ray-traced lighting passes on "
                 "captured GBuffers, pass by pass, from a JSON config"};
    app.require_subcommand(1);
    // Global options may come after the subcommand too (`framepass run cfg.json --threads 2`):
    // subcommands made after this inherit it and hand options they do not know to the app.
    app.fallthrough();
    int threads = 0;
    bool verbose = false, quiet = false;
    // Bounded: each thread is created up front (oneTBB, OpenEXR's pool), and tens of thousands
    // of them end in std::system_error instead of a usage error.
    app.add_option("--threads", threads, "worker threads (0 = all cores); output is identical "
                                         "for any value")
        ->check(CLI::Range(0, fp::limits::kMaxThreads)
                    .description(fmt::format("0..{} (the limit)", fp::limits::kMaxThreads)));
    auto* verboseFlag =
        app.add_flag("-v,--verbose", verbose, "also print each pass's time on stderr as it runs");
    app.add_flag("-q,--quiet", quiet,
                 "print no progress, information or warnings on stderr, "
                 "only errors")
        ->excludes(verboseFlag);
    app.set_version_flag("--version", "framepass " FP_VERSION);

    std::vector<std::pair<CLI::App*, fp::cli::Command>> commands;
    auto add = [&](fp::cli::Command (*fn)(CLI::App&)) {
        const std::size_t before = app.get_subcommands({}).size();
        fp::cli::Command cmd = fn(app);
        commands.emplace_back(app.get_subcommands({})[before], cmd);
    };
    add(fp::cli::addCaptureCommand);
    add(fp::cli::addInspectCommand);
    add(fp::cli::addCompareCommand);
    add(fp::cli::addPlanCommand);
    add(fp::cli::addRunCommand);
    add(fp::cli::addPassesCommand);
    add(fp::cli::addBenchCommand);
    add(fp::cli::addSheetCommand);
    add(fp::cli::addSchemaCommand);
    add(fp::cli::addTuneCommand);
    add(fp::cli::addServeCommand);
    // `framepass version`, as git, docker and kubectl users type it.
    CLI::App* versionCommand = app.add_subcommand("version", "print framepass's version");
    add(fp::cli::addCompletionCommand);

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help, --help-all, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // The first word that is not an option, when it names no subcommand: a typo of one.
        std::vector<std::string> names;
        for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
        std::string hint;
        // A mistyped option (--ouput): the nearest option of the command it was given to.
        const CLI::App* named = nullptr;
        for (int i = 1; i < argc && !named; ++i)
            for (const CLI::App* sub : app.get_subcommands({}))
                if (sub->get_name() == argv[i]) named = sub;
        std::vector<std::string> optionNames;
        for (const CLI::App* owner : {static_cast<const CLI::App*>(&app), named})
            if (owner)
                for (const CLI::Option* o : owner->get_options())
                    for (const std::string& l : o->get_lnames()) optionNames.push_back("--" + l);
        for (int i = 1; i < argc && hint.empty(); ++i) {
            std::string word = argv[i];
            if (word.rfind("--", 0) != 0 || word == "--") continue;
            word = word.substr(0, word.find('='));
            if (std::find(optionNames.begin(), optionNames.end(), word) == optionNames.end()) {
                const std::string guess = fp::didYouMean(word, optionNames);
                if (!guess.empty())
                    hint = fmt::format("\n'{}' is not an option of {}{}", word,
                                       named ? "'framepass " + named->get_name() + "'" : "framepass",
                                       guess);
            }
        }
        for (int i = 1; i < argc && hint.empty(); ++i) {
            const std::string word = argv[i];
            if (word.empty() || word[0] == '-') {
                if (word == "--threads") ++i;  // its value
                continue;
            }
            if (std::find(names.begin(), names.end(), word) == names.end())
                hint = fmt::format("\n'{}' is not a framepass command{}; the commands: {}", word,
                                   fp::didYouMean(word, names), fmt::join(names, ", "));
            break;
        }
        std::cerr << "framepass error: " << e.what() << hint
                  << "\nRun 'framepass --help' (or 'framepass COMMAND --help') for the options.\n";
        return int(fp::ExitCode::Usage);
    }
    if (versionCommand->parsed()) {
        std::cout << "framepass " FP_VERSION "\n";
        return 0;
    }

    std::unique_ptr<tbb::global_control> limit;
    // OpenEXR compresses and decompresses on its own pool, which is off unless sized.
    const int cores = std::max(1, int(std::thread::hardware_concurrency()));
    Imf::setGlobalThreadCount(threads > 0 ? std::min(threads, cores) : cores);
    if (threads > 0) {
        limit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, threads);
        OIIO::attribute("threads", threads);
    }
    fp::app::Invocation invocation;
    invocation.version = FP_VERSION;
    invocation.arguments.assign(argv, argv + argc);
    invocation.threadsRequested = threads;
    invocation.threads =
        int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    invocation.verbosity = quiet     ? fp::app::Verbosity::Quiet
                           : verbose ? fp::app::Verbosity::Verbose
                                     : fp::app::Verbosity::Normal;
    fp::app::setInvocation(invocation);
    try {
        for (auto& [sub, run] : commands)
            if (sub->parsed()) return run();
    } catch (const fp::Error& e) {
        std::cerr << "framepass error: " << e.what()
                  << (std::string(e.what()).back() == '\n' ? "" : "\n")
                  << "Full command line was:\n> " << fp::app::invocation().commandLine() << "\n";
        return int(e.code());
    } catch (const std::bad_alloc&) {
        std::cerr << "framepass error: out of memory\nFull command line was:\n> "
                  << fp::app::invocation().commandLine() << "\n";
        return int(fp::ExitCode::FrameFailed);
    } catch (const std::exception& e) {
        std::cerr << "framepass internal error: " << e.what() << "\n";
        return int(fp::ExitCode::FrameFailed);
    }
    return 0;
}
