#include "vtkPrismoidVolumeRepresentation.h"

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
