#include "vtkPrismoidVolumeRepresentation.h"

#include <vtkDataObject.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkPVView.h>
#include <vtkUnstructuredGridBase.h>
#include <vtkObjectFactory.h>

#include "vtkPrismoidVolumeMapper.h"

vtkStandardNewMacro(vtkPrismoidVolumeRepresentation);

vtkPrismoidVolumeRepresentation::vtkPrismoidVolumeRepresentation() : Mapper(vtkPrismoidVolumeMapper::New()) {
  this->AddVolumeMapper(MapperName, this->Mapper);
  this->Superclass::SetActiveVolumeMapper(MapperName);
}

void vtkPrismoidVolumeRepresentation::SetActiveVolumeMapper(const char*) { this->Superclass::SetActiveVolumeMapper(MapperName); }

vtkPrismoidVolumeRepresentation::~vtkPrismoidVolumeRepresentation() { this->Mapper->Delete(); }

void vtkPrismoidVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent) { this->Superclass::PrintSelf(os, indent); }

void vtkPrismoidVolumeRepresentation::SetPrismoidBackend(int backend) {
  this->Mapper->SetBackend(backend);
  this->Modified();  // a drawing setting: no data to move again
}

void vtkPrismoidVolumeRepresentation::SetPrismoidOrdering(int ordering) {
  this->Mapper->SetOrdering(ordering);
  this->Modified();  // a drawing setting: no data to move again
}

void vtkPrismoidVolumeRepresentation::SetPrismoidQuantity(int quantity) {
  this->Mapper->SetQuantity(quantity);
  this->Modified();  // a drawing setting: no data to move again
}

double vtkPrismoidVolumeRepresentation::GetPrismoidLastFrameMilliseconds() { return this->Mapper->GetLastFrameMilliseconds(); }
int vtkPrismoidVolumeRepresentation::GetPrismoidMeshUploads() { return vtkPrismoidVolumeMapper::GetMeshUploads(); }
int vtkPrismoidVolumeRepresentation::GetPrismoidFieldUploads() { return vtkPrismoidVolumeMapper::GetFieldUploads(); }

void vtkPrismoidVolumeRepresentation::UpdateMapperParameters() {
  this->Superclass::UpdateMapperParameters();
  vtkInformation* info = this->GetInputArrayInformation(0);
  const char* name = info && info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (name && name[0]) {
    this->WarnedNoArray = false;
  } else if (!this->WarnedNoArray) {
    vtkWarningMacro(<< "Prismoid volume: no array to colour by: choose a point or cell array in Coloring (nothing is drawn)");
    this->WarnedNoArray = true;
  }
}

int vtkPrismoidVolumeRepresentation::ProcessViewRequest(vtkInformationRequestKey* request_type, vtkInformation* inInfo,
                                                        vtkInformation* outInfo) {
  const int result = this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo);
  if (result && request_type == vtkPVView::REQUEST_RENDER()) {
    vtkMultiProcessController* ranks = vtkMultiProcessController::GetGlobalController();
    vtkUnstructuredGridBase* input = this->Mapper->GetInput();
    const bool empty = this->Mapper->GetNumberOfInputConnections(0) > 0 && (!input || input->GetNumberOfCells() == 0);
    if (empty && (!ranks || ranks->GetNumberOfProcesses() <= 1)) {
      if (!this->WarnedEmpty) vtkWarningMacro(<< "Prismoid volume: the input has no cells: nothing to draw");
      this->WarnedEmpty = true;
    } else {
      this->WarnedEmpty = false;
    }
  }
  return result;
}
