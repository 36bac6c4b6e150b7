// A file dialog drawn with ImGui (File → Open model, Render → Export): a folder's subfolders and
// the files with one extension, a path field, Up, double click to enter or open. Hand-written
// because neither Debian 12's ImGui 1.86 nor any Debian package offers an ImGui file browser, and a
// native dialog (GTK, portals) would add a toolkit dependency to a GLFW program.
#pragma once

#include <array>
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
    std::filesystem::path dir;          // the folder shown
    std::vector<DirEntry> entries;      // its listing (read when dir changes)
    std::filesystem::path listed;       // the folder `entries` belongs to
    std::string problem;                // why the folder could not be listed
    char path[1024] = "";               // the path field (a file or a folder)
    int selected = -1;                  // index into entries
    float actionRect[4] = {0, 0, 0, 0}; // the Open/Save button last frame (screen px, tests)
};

// Shows `file`'s folder with `file` in the path field (e.g. a proposed name to save as).
void setDialogFile(FileDialogState& st, const std::filesystem::path& file);

// Draws the dialog's body inside an open popup, the path field taking the keyboard when the
// popup appears (typing replaces the path); returns the file the user chose (the action
// button, Enter on a file path, or a double click on a file). `extension` filters the files
// ("" = all); `action` names the button ("Open", or "Save": then a file that exists is marked
// as the one that will be replaced).
std::optional<std::filesystem::path>
drawFileDialog(FileDialogState& st, const std::string& extension, const char* action = "Open");

// Where a panel's Export buttons write (gui/export_buttons.h).
struct ExportState {
    FileDialogState dialog;
    std::string extension; // of the button that opened the dialog
};

// Inside an open popup (a modal dialog, a menu): Escape closes it; true when it did. Not when
// closeTopPopupOnEscape took this frame's Escape for another popup.
bool closeOnEscape();
// Once a frame, before the panels draw: Escape closes the topmost open popup unless it is a modal
// dialog (which closes itself with closeOnEscape, keeping its own state): a combo's list, a
// context menu, a tab bar's list. ImGui 1.86 closes popups on Escape only with keyboard
// navigation on, which the workbench leaves off (arrow keys edit its fields); written by hand for
// that. An Escape that closed a popup here closes nothing else in its frame.
void closeTopPopupOnEscape();

// Recent files: `path` moved to the front, duplicates removed, at most `keep` kept.
void rememberRecent(std::vector<std::string>& recent, const std::string& path, size_t keep = 8);

} // namespace app
