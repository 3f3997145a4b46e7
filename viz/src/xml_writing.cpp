#include "xml_writing.hpp"

#include <cerrno>
#include <cstring>

#include "splitgrid/error.hpp"
#include "vtk_messages.hpp"

#include <vtkXMLWriter.h>

namespace sg::viz::detail {

void write_xml(vtkXMLWriter& writer, const std::string& failure)
{
    VtkMessageCapture messages;
    writer.SetDataModeToAppended();
    writer.EncodeAppendedDataOff();
    writer.SetHeaderTypeToUInt64();
    writer.SetCompressorTypeToZLib();
    errno = 0;
    const int ok = writer.Write();
    const int error = errno;
    const std::string message = messages.first_message();
    if (ok != 1 || writer.GetErrorCode() != 0 || !message.empty()) {
        std::string what = failure;
        if (!message.empty()) what += " (VTK: " + message + ")";
        if (error != 0) what += " (last system error: " + std::string(std::strerror(error)) + ")";
        throw IoError(what);
    }
}

}  // namespace sg::viz::detail
