// gl readback: framebuffer pixels to memory and PNG (stb_image_write from Debian's libstb).
#include "gl.h"

#include "core/core.h"

#include <stb_image_write.h>

namespace gl {

std::vector<unsigned char> readPixelsRGBA8(GLuint fbo, int x, int y, int width, int height) {
    std::vector<unsigned char> pixels(static_cast<size_t>(width) * height * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, y, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    // GL rows are bottom-up; flip to top-down.
    const size_t row = static_cast<size_t>(width) * 4;
    for (int r = 0; r < height / 2; ++r)
        std::swap_ranges(pixels.begin() + r * row, pixels.begin() + (r + 1) * row,
                         pixels.begin() + (height - 1 - r) * row);
    return pixels;
}

std::string encodePng(int width, int height, const std::vector<unsigned char>& rgba) {
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (width <= 0 || height <= 0 || rgba.size() < size_t(width) * size_t(height) * 4 ||
        !stbi_write_png_to_func(append, &bytes, width, height, 4, rgba.data(), width * 4))
        return {};
    return bytes;
}

void writePng(const std::filesystem::path& path, int width, int height,
              const std::vector<unsigned char>& rgba) {
    // encoded in memory, then written atomically (core::writeFile: temporary file + rename)
    const std::string bytes = encodePng(width, height, rgba);
    if (bytes.empty()) throw core::Error(path.string(), 0, "cannot encode the PNG");
    core::writeFile(path, bytes);
}

} // namespace gl
