#pragma once
// Results are written to a temporary file and renamed into place, so an interrupted run never
// leaves a half-written file that looks complete.
#include <string>

namespace heightmarch {

// Throws std::runtime_error naming the path and the system's reason on failure (a full disk:
// "No space left on device"), after removing the temporary; the final path is then untouched.
void write_file_atomically(const std::string& path, const std::string& content);

// The temporary beside path a write of this process uses: "PATH.tmp-PID".
std::string temporary_path(const std::string& path);

}  // namespace heightmarch
