#include "core/error.h"

#include <utility>

namespace patchsim {

namespace {
std::string compose(const std::string& file, const std::string& field, const std::string& message) {
    std::string text = file.empty() ? std::string("<input>") : file;
    if (!field.empty()) text += ": " + field;
    return text + ": " + message;
}
}  // namespace

InputError::InputError(std::string file, std::string field, const std::string& message)
    : std::runtime_error(compose(file, field, message)),
      file_(std::move(file)),
      field_(std::move(field)),
      message_(message) {}

}  // namespace patchsim
