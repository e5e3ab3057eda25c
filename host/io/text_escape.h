#pragma once
// Text from outside (a model path, a device name) made safe for the one-line headers and JSON
// strings every output writes (io/job_metadata.h, io/shard_info.h). A leaf: both include it.
#include <string>
#include <string_view>

namespace shapespline::io {

// `text` as the body of a JSON string: `"` `\` and control characters escaped (\n, \t, \u001f ...),
// invalid UTF-8 replaced by \ufffd. One line, so a model path cannot inject header lines.
std::string escapeText(std::string_view text);

}  // namespace shapespline::io
