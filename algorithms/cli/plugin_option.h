// `--plugin FILE` for cgview run and cgview list: an algorithm file (.cpp,
// built once and cached by content under ~/.cache/cgview/plugins) or a
// built library (.so), loaded before the command looks its algorithm up.
#pragma once

#include <string>
#include <vector>

namespace cgview::cli {

// Removes every "--plugin FILE" from args and loads each plugin.  A file
// that does not compile prints the compiler's diagnostics to stderr and
// throws InvalidInput with their summary.
void take_plugin_options(std::vector<std::string>& args);

}  // namespace cgview::cli
