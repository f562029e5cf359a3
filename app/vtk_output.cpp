/// vtk_output.hpp.
#include "vtk_output.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include "granular/error.hpp"
#include "vtk_xml_file.hpp"

namespace granular::app {

void writeVti(const std::filesystem::path& file, const Vec3& origin, const Vec3& spacing,
              std::array<int, 3> counts, const std::vector<GridArray>& arrays) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(counts[0], counts[1], counts[2]);
  image->SetOrigin(origin.x(), origin.y(), origin.z());
  image->SetSpacing(spacing.x(), spacing.y(), spacing.z());
  const vtkIdType nodes = vtkIdType(counts[0]) * counts[1] * counts[2];
  for (const GridArray& a : arrays) {
    if (vtkIdType(a.values.size()) != nodes * a.components) {
      throw IoError(file.string() + ": array " + a.name + " has the wrong number of values");
    }
    vtkNew<vtkDoubleArray> data;
    data->SetName(a.name.c_str());
    data->SetNumberOfComponents(a.components);
    data->SetNumberOfTuples(nodes);
    for (vtkIdType i = 0; i < nodes * a.components; ++i) data->SetValue(i, a.values[i]);
    image->GetPointData()->AddArray(data);
  }
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetInputData(image);
  writeVtkXml(*writer, file);
}

void writeVtpLines(const std::filesystem::path& file, const std::vector<std::vector<Vec3>>& lines) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkIntArray> ids;
  ids->SetName("line");
  for (std::size_t l = 0; l < lines.size(); ++l) {
    cells->InsertNextCell(vtkIdType(lines[l].size()));
    for (const Vec3& p : lines[l])
      cells->InsertCellPoint(points->InsertNextPoint(p.x(), p.y(), p.z()));
    ids->InsertNextValue(static_cast<int>(l));
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(cells);
  poly->GetCellData()->AddArray(ids);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  writeVtkXml(*writer, file);
}

}  // namespace granular::app
