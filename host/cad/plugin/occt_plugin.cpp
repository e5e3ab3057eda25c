// libshapespline-occt.so: cad::convertPart behind the C entry the CLI looks up (cad/part_plugin.h).
// Only this entry is exported; the static libraries inside are hidden (--exclude-libs), so the
// plugin's copies of core and io never interpose on the executable's.
#include <shapespline/cad/part_plugin.h>

#include <new>
#include <stdexcept>
#include <type_traits>

extern "C" __attribute__((visibility("default"))) void shapespline_convert_part_v1(
    const char* part, const shapespline::cad::ImportOptions& options, shapespline::cad::ConvertedPart& out,
    shapespline::cad::PluginFailure& failure) {
  using shapespline::cad::PluginFailure;
  try {
    out = shapespline::cad::convertPart(part, options);
  } catch (const shapespline::cad::CadError& e) {
    failure = {PluginFailure::Kind::Cad, e.file(), e.entity(), e.reason()};
  } catch (const std::invalid_argument& e) {
    failure = {PluginFailure::Kind::BadInput, "", "", e.what()};
  } catch (const std::bad_alloc&) {
    failure = {PluginFailure::Kind::OutOfMemory, "", "", "out of memory"};
  } catch (const std::exception& e) {
    failure = {PluginFailure::Kind::Runtime, "", "", e.what()};
  } catch (...) {
    failure = {PluginFailure::Kind::Runtime, "", "", "unknown error inside Open CASCADE"};
  }
}

// The entry's type is the one the CLI calls through.
static_assert(std::is_same_v<decltype(&shapespline_convert_part_v1), shapespline::cad::ConvertPartFn>);
