/// wall_cells.hpp.
#include "wall_cells.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataReader.h>

#include "granular/error.hpp"

namespace granular::app {

namespace {

/// Keeps the first message VTK raises on the reader; observing the event stops VTK from printing
/// it, so that the user reads one error naming the file.
void keepFirstMessage(vtkObject*, unsigned long, void* clientData, void* callData) {
  std::string& message = *static_cast<std::string*>(clientData);
  if (message.empty() && callData) message = static_cast<const char*>(callData);
}

Vec3 boxCorner(vtkFieldData* data, const char* name, const std::filesystem::path& file) {
  vtkDataArray* a = data ? data->GetArray(name) : nullptr;
  if (!a || a->GetNumberOfComponents() != 3 || a->GetNumberOfTuples() < 1) {
    throw IoError(file.string() + ": no field array '" + std::string(name) + "' of 3 components");
  }
  return Vec3(a->GetComponent(0, 0), a->GetComponent(0, 1), a->GetComponent(0, 2));
}

}  // namespace

SnapshotWalls readSnapshotWalls(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw IoError(file.string() + ": cannot open");
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  std::string message;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(keepFirstMessage);
  observer->SetClientData(&message);
  reader->AddObserver(vtkCommand::ErrorEvent, observer);
  reader->AddObserver(vtkCommand::WarningEvent, observer);
  // The pipeline that runs the reader says a failed read once more, on its own object.
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, observer);
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (!poly || reader->GetErrorCode() != 0 || !message.empty()) {
    throw IoError(file.string() + ": VTK cannot read it as poly data (.vtp)");
  }
  SnapshotWalls out;
  vtkFieldData* field = poly->GetFieldData();
  out.boxMin = boxCorner(field, "box_min_m", file);
  out.boxMax = boxCorner(field, "box_max_m", file);
  auto* names =
      field ? vtkStringArray::SafeDownCast(field->GetAbstractArray("wall_name")) : nullptr;
  if (!names) throw IoError(file.string() + ": no field array 'wall_name'");
  out.walls.resize(std::size_t(names->GetNumberOfValues()));
  for (std::size_t w = 0; w < out.walls.size(); ++w) {
    out.walls[w].name = names->GetValue(vtkIdType(w));
  }
  vtkDataArray* wall = poly->GetCellData()->GetArray("wall");
  vtkDataArray* shape = poly->GetCellData()->GetArray("shape");
  const vtkIdType cells = poly->GetNumberOfCells();
  if (cells > 0 && (!wall || !shape || wall->GetNumberOfTuples() != cells ||
                    shape->GetNumberOfTuples() != cells)) {
    throw IoError(file.string() + ": no cell arrays 'wall' and 'shape' of one value a cell");
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cells; ++c) {
    const double index = wall->GetComponent(c, 0);
    if (!(index >= 0 && index < double(out.walls.size()))) {
      throw IoError(file.string() + ": cell " + std::to_string(c) + " names wall " +
                    std::to_string(index) + " of " + std::to_string(out.walls.size()));
    }
    WallCells& w = out.walls[std::size_t(index)];
    w.shape = int(shape->GetComponent(c, 0));
    poly->GetCellPoints(c, ids);
    std::vector<Vec3>& corners = w.cells.emplace_back();
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      double x[3];
      poly->GetPoint(ids->GetId(k), x);
      corners.emplace_back(x[0], x[1], x[2]);
    }
  }
  return out;
}

}  // namespace granular::app
