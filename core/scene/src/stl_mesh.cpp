/// Reading STL files (granular/stl_mesh.hpp). VTK parses the file; the checks VTK does not make
/// (a binary file's length against its triangle count, which VTK ignores and reads to the end)
/// come before it, and the mesh's own defects after it.
#include "granular/stl_mesh.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>

#include "granular/error.hpp"
#include "granular/output_file.hpp"

namespace granular {

namespace {

constexpr std::uint64_t kBinaryHeader = 84;    // 80 bytes of text, a 4-byte triangle count
constexpr std::uint64_t kBinaryTriangle = 50;  // normal, 3 corners (12 floats), 2 spare bytes

/// VTK's error and warning messages, kept instead of printed.
struct VtkMessages {
  std::string text;
  static void keep(vtkObject*, unsigned long, void* self, void* message) {
    auto* messages = static_cast<VtkMessages*>(self);
    if (messages->text.empty() && message) messages->text = static_cast<const char*>(message);
  }
};

/// A binary file's triangle count against its length; ASCII files ("solid" and text) pass.
void checkBinaryLength(const std::filesystem::path& file) {
  InputFile in(file, "STL mesh");
  const std::uint64_t size = in.size();
  const std::string name = file.string();
  if (size == 0) throw SceneError(name + ": the STL file is empty");
  const std::string head = in.read(0, std::min<std::uint64_t>(size, 512));
  const bool text =
      head.rfind("solid", 0) == 0 && std::none_of(head.begin(), head.end(), [](char c) {
        return static_cast<unsigned char>(c) > 127 || c == '\0';
      });
  if (text) return;
  if (size < kBinaryHeader) {
    throw SceneError(name + ": a binary STL file of " + std::to_string(size) +
                     " bytes, shorter than its 84-byte header: truncated");
  }
  std::uint32_t count = 0;
  const std::string field = in.read(80, 4);
  std::memcpy(&count, field.data(), sizeof count);
  if (count == 0 && size == kBinaryHeader) {
    throw SceneError(name + ": the STL file holds no triangle (its binary header announces 0)");
  }
  const std::uint64_t expected = kBinaryHeader + kBinaryTriangle * std::uint64_t(count);
  if (size != expected) {
    throw SceneError(
        name + ": the binary STL header announces " + std::to_string(count) + " triangles (" +
        std::to_string(expected) + " bytes) but the file has " + std::to_string(size) +
        " bytes: " + (size < expected ? "truncated" : "padded, or a wrong triangle count"));
  }
}

/// The corners of every triangle welded where they coincide exactly (sorted, so the numbering
/// is the same on every machine).
TriangleMesh welded(const std::vector<Vec3>& corners) {
  std::vector<std::uint32_t> order(corners.size());
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](std::uint32_t k) {
    return std::make_tuple(corners[k].x(), corners[k].y(), corners[k].z());
  };
  // NaN corners are refused by meshTopology; keep them apart here (each its own vertex).
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return corners[a].allFinite() && corners[b].allFinite() ? key(a) < key(b)
                                                            : corners[a].allFinite();
  });
  TriangleMesh mesh;
  std::vector<std::uint32_t> vertexOf(corners.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Vec3& c = corners[order[k]];
    const bool same = k > 0 && c.allFinite() && corners[order[k - 1]].allFinite() &&
                      key(order[k]) == key(order[k - 1]);
    if (!same) mesh.vertex.push_back(c);
    vertexOf[order[k]] = std::uint32_t(mesh.vertex.size() - 1);
  }
  for (std::size_t t = 0; 3 * t + 2 < corners.size(); ++t) {
    mesh.triangle.push_back({vertexOf[3 * t], vertexOf[3 * t + 1], vertexOf[3 * t + 2]});
  }
  return mesh;
}

/// The first defect, and the other triangles that have one (a triangle's edges may each).
std::string defectText(const std::string& name, const std::vector<MeshDefect>& defects) {
  std::vector<std::size_t> others;
  for (const MeshDefect& d : defects) {
    if (d.triangle != defects.front().triangle &&
        std::find(others.begin(), others.end(), d.triangle) == others.end()) {
      others.push_back(d.triangle);
    }
  }
  std::string text =
      name + ": triangle " + std::to_string(defects.front().triangle) + ": " + defects.front().what;
  if (!others.empty()) {
    text += " (and " + std::to_string(others.size()) + " more triangle" +
            (others.size() > 1 ? "s" : "") + " with defects:";
    for (std::size_t k = 0; k < std::min<std::size_t>(others.size(), 5); ++k) {
      text += " " + std::to_string(others[k]);
    }
    text += others.size() > 5 ? " ...)" : ")";
  }
  return text;
}

}  // namespace

TriangleMesh readStlMesh(const std::filesystem::path& file, bool closed) {
  const std::string name = file.string();
  checkBinaryLength(file);
  VtkMessages messages;
  vtkNew<vtkCallbackCommand> keep;
  keep->SetCallback(&VtkMessages::keep);
  keep->SetClientData(&messages);
  vtkNew<vtkSTLReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, keep);
  reader->AddObserver(vtkCommand::WarningEvent, keep);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, keep);  // "returned failure"
  reader->GetExecutive()->AddObserver(vtkCommand::WarningEvent, keep);
  reader->SetFileName(name.c_str());
  reader->MergingOff();  // every triangle keeps its own corners, in the file's order
  reader->Update();
  if (!messages.text.empty()) {
    // VTK's message starts with its class and address: keep what it says.
    std::string what = messages.text;
    const std::size_t colon = what.find("): ");
    if (colon != std::string::npos) what = what.substr(colon + 3);
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    throw SceneError(name + ": not a readable STL file: " + what);
  }
  vtkPolyData* poly = reader->GetOutput();
  vtkCellArray* polys = poly->GetPolys();
  std::vector<Vec3> corners;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; polys && c < polys->GetNumberOfCells(); ++c) {
    polys->GetCellAtId(c, ids);
    if (ids->GetNumberOfIds() != 3) continue;
    for (vtkIdType k = 0; k < 3; ++k) {
      double x[3];
      poly->GetPoint(ids->GetId(k), x);
      corners.push_back(Vec3(x[0], x[1], x[2]));
    }
  }
  if (corners.empty()) throw SceneError(name + ": the STL file holds no triangle");
  TriangleMesh mesh = welded(corners);
  std::vector<MeshDefect> defects;
  meshTopology(mesh, closed, defects);
  if (!defects.empty()) throw SceneError(defectText(name, defects));
  return mesh;
}

}  // namespace granular
