#pragma once

#include <string>

#include <vtkLogger.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>
#include <vtkStringOutputWindow.h>

namespace sg::viz::detail {

/// While alive, VTK's error and warning texts (which VTK prints to stderr by default, through
/// its output window and through its logger) are collected instead, so that the library
/// prints nothing and a writer's complaint can become part of an exception's message.
/// Changes VTK's global output window and logger verbosity, restoring them afterwards: not
/// for concurrent use with other VTK code that relies on them.
class VtkMessageCapture {
public:
    VtkMessageCapture();
    ~VtkMessageCapture();
    VtkMessageCapture(const VtkMessageCapture&) = delete;
    VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;

    /// The first message's text without VTK's "ERROR: In file, line" prefix and object
    /// address, on one line; empty if VTK said nothing.
    [[nodiscard]] std::string first_message();

private:
    vtkSmartPointer<vtkStringOutputWindow> capture_;
    vtkSmartPointer<vtkOutputWindow> previous_;
    vtkLogger::Verbosity previous_verbosity_;
};

}  // namespace sg::viz::detail
