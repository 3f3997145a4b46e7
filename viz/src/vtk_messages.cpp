#include "vtk_messages.hpp"

#include <sstream>

namespace sg::viz::detail {
namespace {

/// "vtkFoo (0x55d0): Algorithm vtkBar(0x55d1) returned failure for request: vtkInformation
/// (0x55d2)" -> "Algorithm vtkBar returned failure": object addresses and the pipeline
/// request mean nothing to a user.
std::string without_addresses(std::string line)
{
    const std::size_t text_start = line.find("): ");
    if (text_start != std::string::npos) line.erase(0, text_start + 3);
    const std::size_t request = line.find(" for request:");
    if (request != std::string::npos) line.erase(request);
    for (std::size_t at = line.find("(0x"); at != std::string::npos; at = line.find("(0x", at)) {
        const std::size_t close = line.find(')', at);
        if (close == std::string::npos) break;
        line.erase(at, close + 1 - at);
    }
    return line;
}

}  // namespace

VtkMessageCapture::VtkMessageCapture()
    : capture_(vtkSmartPointer<vtkStringOutputWindow>::New()),
      previous_(vtkOutputWindow::GetInstance()),
      previous_verbosity_(vtkLogger::GetCurrentVerbosityCutoff())
{
    vtkOutputWindow::SetInstance(capture_);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

VtkMessageCapture::~VtkMessageCapture()
{
    vtkLogger::SetStderrVerbosity(previous_verbosity_);
    vtkOutputWindow::SetInstance(previous_);
}

std::string VtkMessageCapture::first_message()
{
    // A message reads "ERROR: In <source file>, line <n>\n<Class> (<address>): <text>\n...";
    // the line after the first "In <file>, line" line carries the text.
    std::istringstream lines(capture_->GetOutput());
    std::string line;
    bool next_is_text = false;
    while (std::getline(lines, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (line.find(": In ") != std::string::npos && line.find(", line ") != std::string::npos) {
            next_is_text = true;
            continue;
        }
        if (next_is_text && !line.empty()) return without_addresses(line);
    }
    return {};
}

}  // namespace sg::viz::detail
