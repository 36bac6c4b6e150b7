// The table of commands (command.h), in the order --help lists them. Each entry is made in the
// command's own file; adding a command is that file and one line here.
#include "cli/command.h"

namespace app {

Command guiCommand();               // gui_commands.cpp
Command screenshotCommand();        // gui_commands.cpp
Command profileCommand();           // model_commands.cpp
Command invertCommand();            // model_commands.cpp
Command newModelCommand();          // model_commands.cpp
Command recordCommand();            // capture_commands.cpp
Command defaultsCommand();          // defaults_command.cpp
Command replayCommand();            // capture_commands.cpp
Command slabCommand();              // slab_command.cpp
Command estimateCommand();          // estimate_commands.cpp
Command compareCommand();           // compare_command.cpp
Command fitCommand();               // fit_command.cpp
Command paramsLabCommand();         // params_lab_command.cpp
Command mergeCommand();             // estimate_commands.cpp
Command sphereCommand();            // image_commands.cpp
Command meshCommand();              // image_commands.cpp
Command integrateCommand();         // integrate_command.cpp
Command pointcloudCommand();        // pointcloud_command.cpp
Command renderCommand();            // render_command.cpp
Command benchGroup();               // bench_commands.cpp
Command benchReloadCommand();       // bench_commands.cpp
Command benchPathtraceCommand();    // bench_commands.cpp
Command benchSamplingCommand();     // bench_commands.cpp
Command benchConvergenceCommand();  // bench_commands.cpp
Command benchTextureSpaceCommand(); // bench_commands.cpp
Command benchHierarchyCommand();    // bench_commands.cpp
Command probeModelCommand();        // probe_commands.cpp
Command probeServerCommand();       // probe_commands.cpp

const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        guiCommand(), // first: it runs when the command line names none
        screenshotCommand(),
        profileCommand(),
        invertCommand(),
        newModelCommand(),
        recordCommand(),
        defaultsCommand(),
        replayCommand(),
        slabCommand(),
        estimateCommand(),
        compareCommand(),
        fitCommand(),
        paramsLabCommand(),
        mergeCommand(),
        sphereCommand(),
        meshCommand(),
        integrateCommand(),
        pointcloudCommand(),
        renderCommand(),
        benchGroup(),
        benchReloadCommand(),
        benchPathtraceCommand(),
        benchSamplingCommand(),
        benchConvergenceCommand(),
        benchTextureSpaceCommand(),
        benchHierarchyCommand(),
        probeModelCommand(),
        probeServerCommand(),
    };
    return table;
}

} // namespace app
