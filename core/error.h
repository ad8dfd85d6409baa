#pragma once
// Errors that reach the user. An InputError always names the file and the field (or line and
// column) at fault, so the command line can print one clear message and exit non-zero.

#include <stdexcept>
#include <string>

namespace patchsim {

class InputError : public std::runtime_error {
  public:
    InputError(std::string file, std::string field, const std::string& message);

    const std::string& file() const { return file_; }
    const std::string& field() const { return field_; }
    const std::string& message() const { return message_; }  // without the file and field

  private:
    std::string file_;
    std::string field_;
    std::string message_;
};

}  // namespace patchsim
