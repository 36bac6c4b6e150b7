// A file dialog drawn with ImGui (File → Open model): a folder's subfolders and the files with
// one extension, a path field, Up, double click to enter or open. Hand-written because
// neither Debian 12's ImGui 1.86 nor any Debian package offers an ImGui file browser, and a
// native dialog (GTK, portals) would add a toolkit dependency to a GLFW program.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct DirEntry {
    std::string name;
    bool directory = false;
};

// The entries of `dir` shown by the dialog: subfolders, then files ending in `extension`,
// each sorted by name; hidden entries (leading '.') left out. Throws core::Error naming the
// folder when it cannot be read.
std::vector<DirEntry> listDirectory(const std::filesystem::path& dir, const std::string& extension);

struct FileDialogState {
    std::filesystem::path dir;     // the folder shown
    std::vector<DirEntry> entries; // its listing (read when dir changes)
    std::filesystem::path listed;  // the folder `entries` belongs to
    std::string problem;           // why the folder could not be listed
    char path[1024] = "";          // the path field (a file or a folder)
    int selected = -1;             // index into entries
};

// Draws the dialog's body inside an open popup; returns the file the user chose (Open, Enter
// on a file path, or a double click on a file). `extension` filters the files ("" = all).
std::optional<std::filesystem::path> drawFileDialog(FileDialogState& st,
                                                    const std::string& extension);

// Recent files: `path` moved to the front, duplicates removed, at most `keep` kept.
void rememberRecent(std::vector<std::string>& recent, const std::string& path, size_t keep = 8);

} // namespace app
