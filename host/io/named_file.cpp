#include <shapespline/core/model.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/named_file.h>

namespace shapespline::io {

std::filesystem::path resolveNamedFile(const NamedFileRule& rule, const std::string& name, const std::string& key) {
  const std::string shown = shortText(name);
  if (name.empty()) throw ModelError(key, "\"\"", "the file name is empty");
  const std::filesystem::path rel(name);
  const std::filesystem::path file = rule.folder / rel;
  if (rule.allowOutside) return file;  // the reader names a missing file
  const std::string outside = " is outside the folder of " + rule.namer +
                              " (names are relative to that folder" +
                              (rule.allowHint.empty() ? ")" : "; " + rule.allowHint + ")");
  if (rel.is_absolute()) throw ModelError(key, shown, "an absolute path" + outside);
  // Resolved after every link, then compared with the folder's own resolved path: a link inside
  // that points out, or a `..` that climbs out, both land outside.
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::canonical(rule.folder.empty() ? "." : rule.folder, ec);
  if (ec) throw ModelError(key, shown, "cannot resolve the folder of " + rule.namer + ": " + ec.message());
  const std::filesystem::path real = std::filesystem::weakly_canonical(file, ec);
  if (ec) throw ModelError(key, shown, "cannot resolve the path: " + ec.message());
  const std::filesystem::path up = real.lexically_relative(dir);
  if (up.empty() || *up.begin() == "..") throw ModelError(key, shown, "the file (after links)" + outside);
  if (!std::filesystem::exists(real, ec))
    throw ModelError(key, shown, "no such file in the folder of " + rule.namer + " (cannot open it)");
  return file;
}

}  // namespace shapespline::io
