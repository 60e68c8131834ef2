#include <exception>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "hullmap/mapper/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hullmap: SLAM map points -> OctoMap -> DBSCAN clusters -> convex obstacles -> path checks"};
  app.set_version_flag("--version", HULLMAP_VERSION);
  app.require_subcommand(1);
  int status = 0;
  hullmap::cli::addBuildCommand(app, status);
  hullmap::cli::addInfoCommand(app, status);
  hullmap::cli::addGenerateCommand(app, status);
  hullmap::cli::addClusterCommand(app, status);
  hullmap::cli::addSweepCommand(app, status);
  hullmap::cli::addCheckCommand(app, status);
  hullmap::cli::addPlotCommand(app, status);
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known) {
    std::cerr << "hullmap: error: unknown subcommand '" << argv[1] << "' (expected one of " << names << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "hullmap: error: " << e.what() << " (see hullmap --help)\n";
    return 2;
  } catch (const hullmap::Error& e) {
    std::cerr << "hullmap: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "hullmap: error: out of memory\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hullmap: error: " << e.what() << "\n";
    return 2;
  }
  return status;
}
