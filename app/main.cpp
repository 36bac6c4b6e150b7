// bssrdf-workbench: develop, inspect and validate analytic BSSRDF models. Runs the command the
// command line names (the table: cli/commands.cpp; none: the GUI, `gui`). Everything but a
// windowed `gui` runs without a display.
#include "cli/command.h"

int main(int argc, char** argv) {
    return app::runCommandLine(argc, argv);
}
