// topotet: command-line front end of the library (see docs/cli.md).
//
// main() parses with CLI11, runs the selected command and turns every error into one line on
// stderr and exit code 2: bad usage (CLI11 parse errors), bad input (topotet::InputError) and any
// other std::exception. A failed check (topology, inverted tets) is exit code 1.
//
// SIGINT and SIGTERM remove the temporary files of writes in progress and out-of-core scratch folders (outputs already written
// stay; a file being written keeps its old content), print one error line and exit 130 / 143,
// the codes a shell gives a process killed by those signals.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "common.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/out_of_core.h"
#include "topotet/version.h"

namespace {

// Async-signal-safe: unlink, write and _exit only.
extern "C" void on_terminate_signal(int sig) {
  topotet::remove_temporary_files();
  topotet::remove_out_of_core_scratch();
  static const char kInt[] = "topotet: error: interrupted (SIGINT)\n";
  static const char kTerm[] = "topotet: error: terminated (SIGTERM)\n";
  const char* text = sig == SIGINT ? kInt : kTerm;
  const std::size_t size = sig == SIGINT ? sizeof kInt - 1 : sizeof kTerm - 1;
  [[maybe_unused]] const ssize_t n = ::write(2, text, size);
  ::_exit(128 + sig);
}

void install_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_terminate_signal;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);  // one handler at a time
  sigaddset(&action.sa_mask, SIGTERM);
  for (int sig : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    // A signal ignored by the parent (nohup, background jobs of a non-interactive shell) stays ignored.
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &action, nullptr);
  }
}

// One line, whatever the message holds.
void print_error(const std::string& message) {
  std::string line = message;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  std::fprintf(stderr, "topotet: error: %s\n", line.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace topotet::cli;
  install_signal_handlers();
  CLI::App app{"topotet: simplify tetrahedral meshes by edge collapses, keeping the topology of the mesh and of "
               "every embedded surface, interface, polyline and pinned vertex."};
  app.name("topotet");
  app.require_subcommand(1);
  app.set_version_flag("--version", "topotet " TOPOTET_VERSION_STRING);

  CommandRunner run;
  add_info_command(app, run);
  add_generate_command(app, run);
  add_convert_command(app, run);
  add_simplify_command(app, run);
  add_check_command(app, run);
  add_demo_command(app, run);
  add_extract_command(app, run);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error(std::string(e.what()) + " (run 'topotet --help')");
    return kExitBadInput;
  }

  try {
    return run ? run() : kExitBadInput;
  } catch (const topotet::InputError& e) {
    print_error(e.what());
  } catch (const std::bad_alloc&) {
    print_error("out of memory");
  } catch (const std::exception& e) {
    print_error(e.what());
  } catch (...) {
    print_error("unknown error");
  }
  return kExitBadInput;
}
