// File and process helpers of the mbest executable. Outputs are written with
// mbest/core/atomic_file.h.
#pragma once

#include <atomic>
#include <string>

#include "mbest/core/result.h"

namespace mbest::app {

// Creates `dir` and its parents; the error names the folder.
Status make_dirs(const std::string& dir);

// The JSON text of an option such as --config: `value` itself when it is an inline object
// (its first non-blank character is '{'), else the contents of the file it names; `source`
// names it in messages (the option, or the file). The error names the option and the file.
struct JsonOption {
  std::string text, source;
};
Result<JsonOption> json_option(const std::string& option, const std::string& value);

// From the first call on, SIGINT and SIGTERM no longer end the process: they set the flag
// returned, which long runs check between items so that what they write stays whole.
const std::atomic<bool>& catch_interrupts();

}  // namespace mbest::app
