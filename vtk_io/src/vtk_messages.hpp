#pragma once
// VTK's error messages, captured instead of printed, for the readers and writers of vtk_io.

#include <vtkAlgorithm.h>
#include <vtkErrorCode.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace rgbmesh::detail {

// Keeps VTK's error texts instead of printing them.
class MessageCollector : public vtkOutputWindow {
 public:
  static MessageCollector* New();
  vtkTypeMacro(MessageCollector, vtkOutputWindow)  // (a macro that ends its own declarations)

      // vtkOutputWindow routes every message type through DisplayText.
      void DisplayText(const char* text) override {
    if (text != nullptr && this->GetCurrentMessageType() == MESSAGE_TYPE_ERROR) errors.emplace_back(text);
  }

  std::vector<std::string> errors;
};

// While alive, VTK prints nothing: its output window is replaced by a collector, and its logger
// (which writes errors to stderr on its own, before the output window sees them) is silenced.
// Both are process-wide, so VTK work is serialized.
class CapturedVtkMessages {
 public:
  CapturedVtkMessages() : lock_(vtk_mutex()), previous_window_(vtkOutputWindow::GetInstance()) {
    // SetInstance deletes the window it replaces; the extra reference keeps it for restoring.
    previous_window_->Register(nullptr);
    vtkOutputWindow::SetInstance(collector_);
    // vtkLogger has no getter for the stderr level; the cutoff equals it unless a log file or
    // callback asks for more.
    previous_verbosity_ = vtkLogger::GetCurrentVerbosityCutoff();
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~CapturedVtkMessages() {
    vtkLogger::SetStderrVerbosity(previous_verbosity_);
    vtkOutputWindow::SetInstance(previous_window_);
    previous_window_->UnRegister(nullptr);
  }
  CapturedVtkMessages(const CapturedVtkMessages&) = delete;
  CapturedVtkMessages& operator=(const CapturedVtkMessages&) = delete;

  // The first error that says something, as one printable line. VTK's texts read
  // "ERROR: In <source>, line <n>\n<class> (0x...): <message>\n\n"; the location and the object
  // address mean nothing to a user. The pipeline's "Algorithm <class> ... returned failure for
  // request" only repeats that the algorithm (a reader or a writer) failed, so it is used only
  // when there is nothing else, as "<class> failed without saying why".
  std::string first_error() const {
    std::string fallback;
    for (const std::string& text : collector_->errors) {
      const std::string message = message_of(text);
      if (message.empty()) continue;
      if (message.rfind("Algorithm ", 0) != 0) return message;
      if (fallback.empty()) {
        constexpr std::size_t name_at = sizeof "Algorithm " - 1;
        const std::size_t name_end = message.find_first_of(" (", name_at);
        const std::string name = message.substr(name_at, name_end - name_at);
        fallback = (name.rfind("vtk", 0) == 0 ? name : std::string("VTK")) + " failed without saying why";
      }
    }
    return fallback;
  }

 private:
  static std::mutex& vtk_mutex() {
    static std::mutex mutex;
    return mutex;
  }

  std::lock_guard<std::mutex> lock_;
  vtkOutputWindow* previous_window_;
  vtkNew<MessageCollector> collector_;
  vtkLogger::Verbosity previous_verbosity_ = vtkLogger::VERBOSITY_OFF;

  static std::string message_of(const std::string& text) {
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.rfind("ERROR: In ", 0) == 0) continue;
      const auto address = line.find("(0x");
      const auto colon = line.find("): ");
      if (address != std::string::npos && colon != std::string::npos && address < colon)
        line.erase(0, colon + 3);
      for (char& c : line)
        if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
      while (!line.empty() && line.back() == ' ') line.pop_back();
      constexpr std::size_t longest = 200;
      if (line.size() > longest) line = line.substr(0, longest) + "...";
      if (!line.empty()) return line;
    }
    return "";
  }
};

// Runs a reader; any VTK error or error code is an InputError naming the file.
void run_reader(vtkAlgorithm& reader, const std::filesystem::path& path);

// Runs a writer whose file name is set (VTK's XML writers are no vtkWriter, hence the template);
// any VTK error or error code is a failure.
template <class Writer>
void run_writer(Writer& writer) {
  CapturedVtkMessages messages;
  const int written = writer.Write();
  std::string error = messages.first_error();
  if (error.empty() && writer.GetErrorCode() != vtkErrorCode::NoError)
    error = vtkErrorCode::GetStringFromErrorCode(writer.GetErrorCode());
  if (error.empty() && written != 1) error = "the VTK writer failed";
  if (!error.empty()) throw std::runtime_error(error);
}

}  // namespace rgbmesh::detail
