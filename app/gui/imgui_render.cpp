#include "gui/imgui_render.h"

#include "gl/gl.h"

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdint>

namespace app {

void renderImGuiDrawData() {
    ImDrawData* data = ImGui::GetDrawData();
    if (gl::barrierChecksActive() && data)
        for (int i = 0; i < data->CmdListsCount; ++i)
            for (const ImDrawCmd& cmd : data->CmdLists[i]->CmdBuffer)
                gl::checkTextureFetch(
                    static_cast<GLuint>(reinterpret_cast<std::intptr_t>(cmd.GetTexID())),
                    "ImGui's draw");
    ImGui_ImplOpenGL3_RenderDrawData(data);
}

} // namespace app
