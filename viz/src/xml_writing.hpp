#pragma once

#include <string>

class vtkXMLWriter;

/// The one encoding of every VTK XML file splitgrid writes, and the one way a failed write
/// becomes an exception.
namespace sg::viz::detail {

/// Writes through `writer`, whose input and file name the caller has set, as appended raw
/// binary with 64-bit block headers, zlib compressed: the compact encoding (base64 adds a
/// third), and 64-bit headers allow arrays over 4 GiB. A composite writer hands these settings
/// to the writer of each block. On failure throws IoError "<failure>", followed by VTK's first
/// message and the last system error where there are any (VTK's XML writers report a full
/// disk or a file size limit only as a failed pipeline request, so the system's error code is
/// the only hint of the cause). VTK's own messages are captured, never printed.
void write_xml(vtkXMLWriter& writer, const std::string& failure);

}  // namespace sg::viz::detail
