// caliper — measurements in, rigged avatars out. See `caliper --help` and docs/cli.md.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "common.h"

int main(int argc, char** argv) {
  CLI::App app{"Caliper: metrically accurate, rigged 3D avatars from a few body measurements.\n"
               "Lengths are in centimetres and weight in kilograms at the command line."};
  app.set_version_flag("--version", std::string("caliper ") + CALIPER_CLI_VERSION);
  app.require_subcommand(1);
  // Before any command runs, so every model lookup (library and server alike) sees it.
  app.add_option_function<std::string>(
         "--models",
         [](const std::string& dir) {
           if (!std::filesystem::is_directory(dir))
             throw CLI::ValidationError("--models", "there is no folder '" + dir + "'");
           ::setenv("CALIPER_MODELS_DIR", dir.c_str(), 1);
         },
         "folder of the body models found by name (default: $CALIPER_MODELS_DIR, else the installation's "
         "share/caliper/models; docs/cli.md)")
      ->type_name("DIR");
  app.fallthrough(false);
  caliper::cli::register_avatar(app);
  caliper::cli::register_render(app);
  caliper::cli::register_measure(app);
  caliper::cli::register_model(app);
  caliper::cli::register_isak(app);
  caliper::cli::register_map(app);
  caliper::cli::register_eval(app);
  caliper::cli::register_batch(app);
  caliper::cli::register_serve(app);
  caliper::cli::register_sessions(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 says only "A subcommand is required" for a mistyped one: name it.
    if (dynamic_cast<const CLI::RequiredError*>(&e) && argc > 1 && argv[1][0] != '-' && !app.get_subcommands().size()) {
      std::cerr << "caliper: unknown command '" << argv[1] << "'; the commands are listed by `caliper --help`\n";
      return caliper::cli::kUsage;
    }
    const int code = app.exit(e);
    if (code != 0) caliper::cli::explain_parse_error(app, argc, argv);
    return code == 0 ? 0 : caliper::cli::kUsage;
  } catch (const caliper::cli::Finished& f) {
    return f.code;
  } catch (const caliper::Error& e) {
    std::cerr << "caliper: " << e.what() << "\n";
    if (e.from_installation())
      std::cerr << "caliper: this file belongs to Caliper's installation, not to your input: rebuild or reinstall it "
                   "(docs/cli.md, exit code 5)\n";
    return caliper::cli::exit_code_for(e);
  } catch (const std::exception& e) {
    std::cerr << "caliper: internal error: " << e.what() << "\n";
    return caliper::cli::kInternal;
  }
  return 0;
}
