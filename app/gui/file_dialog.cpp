// The ImGui file dialog (file_dialog.h).
#include "gui/file_dialog.h"

#include "core/core.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <cstring>

namespace app {
namespace fs = std::filesystem;

std::vector<DirEntry> listDirectory(const fs::path& dir, const std::string& extension) {
    std::error_code ec;
    fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
    if (ec) throw core::Error(dir.string(), 0, "cannot list the folder: " + ec.message());
    std::vector<DirEntry> dirs, files;
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) break;
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        std::error_code e2;
        if (it->is_directory(e2))
            dirs.push_back({name, true});
        else if (extension.empty() || it->path().extension() == extension)
            files.push_back({name, false});
    }
    auto byName = [](const DirEntry& a, const DirEntry& b) { return a.name < b.name; };
    std::sort(dirs.begin(), dirs.end(), byName);
    std::sort(files.begin(), files.end(), byName);
    dirs.insert(dirs.end(), files.begin(), files.end());
    return dirs;
}

void rememberRecent(std::vector<std::string>& recent, const std::string& path, size_t keep) {
    recent.erase(std::remove(recent.begin(), recent.end(), path), recent.end());
    recent.insert(recent.begin(), path);
    if (recent.size() > keep) recent.resize(keep);
}

namespace {

void setPath(FileDialogState& st, const fs::path& p) {
    std::snprintf(st.path, sizeof st.path, "%s", p.string().c_str());
}

void enter(FileDialogState& st, const fs::path& dir) {
    st.dir = fs::absolute(dir).lexically_normal();
    st.selected = -1;
    setPath(st, st.dir);
}

} // namespace

void setDialogFile(FileDialogState& st, const fs::path& file) {
    const fs::path abs = fs::absolute(file).lexically_normal();
    enter(st, abs.parent_path());
    setPath(st, abs);
}

std::optional<fs::path> drawFileDialog(FileDialogState& st, const std::string& extension,
                                       const char* action) {
    if (st.dir.empty()) enter(st, fs::current_path());
    if (st.listed != st.dir) {
        st.listed = st.dir;
        st.problem.clear();
        try {
            st.entries = listDirectory(st.dir, extension);
        } catch (const core::Error& e) {
            st.entries.clear();
            st.problem = e.what();
        }
    }
    std::optional<fs::path> chosen;
    if (ImGui::Button("Up") && st.dir.has_parent_path()) enter(st, st.dir.parent_path());
    ImGui::SameLine();
    ImGui::SetNextItemWidth(480);
    if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
    const bool typedEnter =
        ImGui::InputText("##dialogpath", st.path, sizeof st.path,
                         ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    ImGui::TextDisabled("%s", st.dir.string().c_str());
    if (!st.problem.empty())
        ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "%s", st.problem.c_str());
    ImGui::BeginChild("entries", ImVec2(560, 300), true);
    for (int i = 0; i < int(st.entries.size()); ++i) {
        const DirEntry& e = st.entries[size_t(i)];
        const std::string label = e.directory ? e.name + "/" : e.name;
        if (ImGui::Selectable(label.c_str(), st.selected == i,
                              ImGuiSelectableFlags_AllowDoubleClick)) {
            st.selected = i;
            setPath(st, st.dir / e.name);
            if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) {
                if (e.directory)
                    enter(st, st.dir / e.name);
                else
                    chosen = st.dir / e.name;
                break;
            }
        }
    }
    if (st.entries.empty() && st.problem.empty())
        ImGui::TextDisabled(extension.empty() ? "(empty folder)" : "(no folders or %s files)",
                            extension.c_str());
    ImGui::EndChild();
    const bool saving = std::strcmp(action, "Save") == 0;
    if (saving) {
        std::error_code ec;
        if (fs::is_regular_file(st.path, ec)) ImGui::TextDisabled("(replaces the existing file)");
    }
    const bool open = ImGui::Button(action);
    {
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        st.actionRect[0] = lo.x, st.actionRect[1] = lo.y, st.actionRect[2] = hi.x,
        st.actionRect[3] = hi.y;
    }
    if ((open || typedEnter) && !chosen) {
        const fs::path p = st.path;
        std::error_code ec;
        if (fs::is_directory(p, ec))
            enter(st, p);
        else
            chosen = p; // a missing or wrong file is the caller's clear error
    }
    return chosen;
}

namespace {
int g_escapeTakenFrame = -1; // the frame whose Escape closeTopPopupOnEscape used
bool escapePressed() {
    return ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false) &&
           g_escapeTakenFrame != ImGui::GetFrameCount();
}
} // namespace

bool closeOnEscape() {
    if (!escapePressed()) return false;
    ImGui::CloseCurrentPopup();
    return true;
}

void closeTopPopupOnEscape() {
    ImGuiContext& g = *ImGui::GetCurrentContext();
    if (g.OpenPopupStack.Size == 0 || !escapePressed()) return;
    const ImGuiWindow* top = g.OpenPopupStack.back().Window;
    if (!top || (top->Flags & ImGuiWindowFlags_Modal)) return;
    ImGui::ClosePopupToLevel(g.OpenPopupStack.Size - 1, true);
    g_escapeTakenFrame = ImGui::GetFrameCount();
}

} // namespace app
