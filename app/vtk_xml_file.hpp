#pragma once
/// VTK's XML writers, made to report like every other writer of granular: VTK serialises into a
/// string, and the file is written from it by writeFileAtomically (checked writes, a temporary
/// renamed into place). VTK's own errors and warnings are taken from the writer as events, so
/// they reach the user as one IoError naming the file rather than as lines of VTK's log.
#include <filesystem>

class vtkXMLWriter;

namespace granular::app {

/// Writes the writer's input (already set) to `file`. IoError naming the file on any failure.
void writeVtkXml(vtkXMLWriter& writer, const std::filesystem::path& file);

}  // namespace granular::app
