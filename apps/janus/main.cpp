// janus: inspect backends, render a scene, and check that all configurations agree.
#include <csignal>
#include <vector>

#include <fmt/format.h>

#include "janus/renderer/image.h"

#include "cli_common.h"

namespace {

using janus::cli::ExitCode;

int usageFailure(const std::string& message, const CLI::App& failedIn) {
    const std::string helpCommand = failedIn.get_parent() ? fmt::format("janus {} --help", failedIn.get_name()) : "janus --help";
    janus::cli::printError(fmt::format("{} (see '{}')", message, helpCommand));
    return static_cast<int>(ExitCode::UsageError);
}

// Ctrl-C, kill, a closed terminal: the files being written are unlinked (their targets keep what
// they held), then the signal takes its default course, so the exit status says which it was.
extern "C" void onTerminatingSignal(int signal) {
    janus::renderer::removeTemporaryFilesNow();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

void handleTerminatingSignals() {
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction action {};
        action.sa_handler = onTerminatingSignal;
        sigemptyset(&action.sa_mask);
        sigaction(signal, &action, nullptr);
    }
    // Past a file size limit (ulimit -f) a write fails with EFBIG and says so, instead of the
    // process dying of SIGXFSZ with its temporary file left behind.
    std::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace

int main(int argc, char** argv) {
    handleTerminatingSignals();
    CLI::App app("janus: renders glTF scenes through one graphics API abstraction on Vulkan, OpenGL and "
                 "OpenGL ES, and checks that every configuration produces the same pixels.",
                 "janus");
    app.footer(janus::cli::kExitCodeHelp);
    app.get_formatter()->column_width(34);

    std::vector<janus::cli::Command> commands = {
        janus::cli::addInfoCommand(app),
        janus::cli::addRenderCommand(app),
        janus::cli::addParityCommand(app),
        janus::cli::addCheckCommand(app),
        janus::cli::addBenchCommand(app),
        janus::cli::addBakeCommand(app),
    };
    app.set_version_flag("--version", "janus " JANUS_VERSION);
    app.require_subcommand(0, 1);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Name the subcommand whose options failed, so the hint points at the right --help.
        const CLI::App* failedIn = &app;
        for (const auto& command : commands)
            if (command.app->parsed()) failedIn = command.app;
        // CLI11 calls a mistyped command an unexpected argument; say what it is.
        if (failedIn == &app && argc > 1 && argv[1][0] != '-')
            return usageFailure(fmt::format("unknown command '{}'; choose one of info, render, parity, check, bench, bake", argv[1]), app);
        return usageFailure(e.what(), *failedIn);
    }

    for (const auto& command : commands)
        if (command.app->parsed()) return janus::cli::runCommand(command.run);

    return usageFailure("no command given; choose one of info, render, parity, check, bench, bake", app);
}
