// The table of commands (command.h), in the order --help lists them. Each entry is made in the
// command's own file; adding a command is that file and one line here.
#include "cli/command.h"

namespace app {

Command guiCommand();               // gui_commands.cpp
Command screenshotCommand();        // gui_commands.cpp
Command profileCommand();           // model_commands.cpp
Command invertCommand();            // model_commands.cpp
Command recordCommand();            // capture_commands.cpp
Command defaultsCommand();          // defaults.cpp
Command replayCommand();            // capture_commands.cpp
Command slabCommand();              // slab.cpp
Command estimateCommand();          // estimate.cpp
Command compareCommand();           // compare.cpp
Command mergeCommand();             // estimate.cpp
Command sphereCommand();            // image.cpp
Command meshCommand();              // image.cpp
Command integrateCommand();         // integrate.cpp
Command pointcloudCommand();        // pointcloud.cpp
Command renderCommand();            // render.cpp
Command benchGroup();               // bench_commands.cpp
Command benchReloadCommand();       // bench_commands.cpp
Command benchPathtraceCommand();    // bench_commands.cpp
Command benchSamplingCommand();     // bench_commands.cpp
Command benchConvergenceCommand();  // bench_commands.cpp
Command benchTextureSpaceCommand(); // bench_commands.cpp
Command benchHierarchyCommand();    // bench_commands.cpp
Command probeModelCommand();        // probe.cpp
Command probeServerCommand();       // probe.cpp

const std::vector<Command>& commands() {
    static const std::vector<Command> table = {
        guiCommand(), // first: it runs when the command line names none
        screenshotCommand(),
        profileCommand(),
        invertCommand(),
        recordCommand(),
        defaultsCommand(),
        replayCommand(),
        slabCommand(),
        estimateCommand(),
        compareCommand(),
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
