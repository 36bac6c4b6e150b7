// core::Error and location formatting.
#include "core.h"

namespace core {

std::string formatLocation(const std::string& file, int line, const std::string& message) {
    if (file.empty()) return message;
    if (line <= 0) return file + ": " + message;
    return file + ":" + std::to_string(line) + ": " + message;
}

// The file name and message are made printable first: both may quote bytes of the input.
Error::Error(std::string file, int line, std::string message)
    : Error(printableText(file), line, printableText(message), 0) {}

Error::Error(std::string file, int line, std::string message, int)
    : std::runtime_error(formatLocation(file, line, message)), m_file(std::move(file)),
      m_line(line), m_message(std::move(message)) {}

} // namespace core
