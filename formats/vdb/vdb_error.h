#pragma once

#include <stdexcept>
#include <string>

namespace firelook::vdb {

// Every failure of the VDB input: the message names the file (or pattern) and the problem.
class VdbError : public std::runtime_error {
  public:
    explicit VdbError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace firelook::vdb
