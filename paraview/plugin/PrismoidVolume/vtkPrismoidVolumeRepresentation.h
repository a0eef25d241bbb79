#ifndef vtkPrismoidVolumeRepresentation_h
#define vtkPrismoidVolumeRepresentation_h
// ParaView's unstructured-grid volume representation with Prismoid's mapper added to its
// mappers (AddVolumeMapper) under the name "Prismoid interval shading", and that mapper's
// settings (backend, ordering, quantity) as properties of the representation.
#include "PrismoidVolumeModuleModule.h"  // export macro
#include <vtkUnstructuredGridVolumeRepresentation.h>

class vtkPrismoidVolumeMapper;

class PRISMOIDVOLUMEMODULE_EXPORT vtkPrismoidVolumeRepresentation : public vtkUnstructuredGridVolumeRepresentation
{
public:
  static vtkPrismoidVolumeRepresentation* New();
  vtkTypeMacro(vtkPrismoidVolumeRepresentation, vtkUnstructuredGridVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  static constexpr const char* MapperName = "Prismoid interval shading";

  // Always Prismoid's mapper: the base proxy's SelectMapper property (not shown for this
  // representation) would otherwise set ParaView's default, projected tetrahedra, at creation.
  void SetActiveVolumeMapper(const char* name) override;

  void SetPrismoidBackend(int backend);
  void SetPrismoidOrdering(int ordering);
  void SetPrismoidQuantity(int quantity);
  vtkPrismoidVolumeMapper* GetPrismoidMapper() { return this->Mapper; }
  // This process's last frame through the plugin: wall ms of its part (0: not drawn).
  double GetPrismoidLastFrameMilliseconds();
  // This process's uploads through the plugin: whole meshes, and fields alone (time steps).
  int GetPrismoidMeshUploads();
  int GetPrismoidFieldUploads();

protected:
  vtkPrismoidVolumeRepresentation();
  ~vtkPrismoidVolumeRepresentation() override;
  vtkPrismoidVolumeMapper* Mapper;
  // The base class's, then a warning (once) where no array is chosen to colour by: ParaView
  // then draws the volume as nothing, its own mappers too.
  void UpdateMapperParameters() override;
  bool WarnedNoArray = false;

public:
  // The base class's; at a render, a warning (once) where the input has no cells in a run of one
  // process (ParaView culls a volume with empty bounds before its mapper could say so).
  int ProcessViewRequest(vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo) override;

protected:
  bool WarnedEmpty = false;

private:
  vtkPrismoidVolumeRepresentation(const vtkPrismoidVolumeRepresentation&) = delete;
  void operator=(const vtkPrismoidVolumeRepresentation&) = delete;
};

#endif
