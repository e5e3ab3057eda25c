// Reading a part file with OCCT's STEP and IGES readers. The checks OCCT does not make come first:
// the file exists, is a regular file, is not empty and is within the size limit.
#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>

#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>

#include <algorithm>
#include <cctype>
#include <mutex>
#include <system_error>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace shapespline::cad {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// OCCT reports on std::cout by default; stdout is ours (the import summary).
void silenceOcct() {
  const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
  messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
}

template <class Reader>
TopoDS_Shape transfer(Reader& reader, const std::string& file, const char* format) {
  const IFSelect_ReturnStatus status = reader.ReadFile(file.c_str());
  if (status != IFSelect_RetDone)
    throw CadError(file, "(file)", std::string("not a readable ") + format + " file (OCCT read status " +
                                       std::to_string(static_cast<int>(status)) + ")");
  if (reader.TransferRoots() == 0) throw CadError(file, "(part)", std::string("the ") + format + " file holds no shape");
  return reader.OneShape();
}

}  // namespace

void initOcctControllers() {
  static std::once_flag once;
  std::call_once(once, [] {
#if defined(__SANITIZE_ADDRESS__)
    __lsan_disable();
#endif
    STEPControl_Controller::Init();
    IGESControl_Controller::Init();
#if defined(__SANITIZE_ADDRESS__)
    __lsan_enable();
#endif
  });
}

PartShape readPart(const std::filesystem::path& path, std::uint64_t maxFileBytes) {
  const std::string file = path.string();
  PartShape part;
  const std::string ext = lowerExtension(path);
  if (ext == ".step" || ext == ".stp") part.format = "step";
  else if (ext == ".iges" || ext == ".igs") part.format = "iges";
  else throw CadError(file, "(file)", "a part must be a STEP (.step, .stp) or IGES (.iges, .igs) file");
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw CadError(file, "(file)", "no such file");
  if (!std::filesystem::is_regular_file(status)) throw CadError(file, "(file)", "not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw CadError(file, "(file)", "cannot read its size: " + ec.message());
  if (bytes == 0) throw CadError(file, "(file)", "the file is empty");
  if (bytes > maxFileBytes)
    throw CadError(file, "(file)", "the file has " + std::to_string(bytes) + " bytes, over the limit of " +
                                       std::to_string(maxFileBytes));
  silenceOcct();
  initOcctControllers();
  try {
    if (part.format == "step") {
      STEPControl_Reader reader;
      part.shape = transfer(reader, file, "STEP");
    } else {
      IGESControl_Reader reader;
      part.shape = transfer(reader, file, "IGES");
    }
    const char* unit = Interface_Static::CVal("xstep.cascade.unit");
    part.units = unit ? unit : "MM";
    std::transform(part.units.begin(), part.units.end(), part.units.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  } catch (const Standard_Failure& e) {
    const char* text = e.GetMessageString();
    throw CadError(file, "(file)", std::string("Open CASCADE failed to read it (") + e.DynamicType()->Name() +
                                       (text && *text ? std::string(": ") + text : "") + ")");
  }
  const bool hasGeometry = part.shape.IsNull() ? false
                                                : TopExp_Explorer(part.shape, TopAbs_FACE).More() ||
                                                      TopExp_Explorer(part.shape, TopAbs_EDGE).More();
  if (!hasGeometry) throw CadError(file, "(part)", "the part holds no faces or edges");
  return part;
}

}  // namespace shapespline::cad
