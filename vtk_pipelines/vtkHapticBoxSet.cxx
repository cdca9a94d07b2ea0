#include "vtkHapticBoxSet.h"
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkHapticBoxSet);

vtkHapticBoxSet::vtkHapticBoxSet() = default;
vtkHapticBoxSet::~vtkHapticBoxSet() = default;

void vtkHapticBoxSet::SetScene(std::shared_ptr<const hb::BoxScene> scene) {
  this->Scene = std::move(scene);
  this->Modified();
}

vtkIdType vtkHapticBoxSet::GetNumberOfBoxes() const {
  return this->Scene ? vtkIdType(this->Scene->parts().boxes.size()) : 0;
}

void vtkHapticBoxSet::Initialize() {
  this->Superclass::Initialize();
  this->Scene.reset();
}

void vtkHapticBoxSet::ShallowCopy(vtkDataObject* src) {
  this->Superclass::ShallowCopy(src);
  if (auto* other = vtkHapticBoxSet::SafeDownCast(src)) this->Scene = other->Scene;
}

void vtkHapticBoxSet::DeepCopy(vtkDataObject* src) {
  // The scene is immutable: sharing it is as good as copying it.
  this->Superclass::DeepCopy(src);
  if (auto* other = vtkHapticBoxSet::SafeDownCast(src)) this->Scene = other->Scene;
}

unsigned long vtkHapticBoxSet::GetActualMemorySize() {
  const std::size_t bytes = this->Scene ? this->Scene->bytes().tables : 0;
  return this->Superclass::GetActualMemorySize() + static_cast<unsigned long>(bytes / 1024);
}

vtkHapticBoxSet* vtkHapticBoxSet::GetData(vtkInformation* info) {
  return info ? vtkHapticBoxSet::SafeDownCast(info->Get(DATA_OBJECT())) : nullptr;
}

vtkHapticBoxSet* vtkHapticBoxSet::GetData(vtkInformationVector* v, int i) {
  return vtkHapticBoxSet::GetData(v->GetInformationObject(i));
}

void vtkHapticBoxSet::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Boxes: " << this->GetNumberOfBoxes() << "\n";
  if (this->Scene) os << indent << "TableBytes: " << this->Scene->bytes().tables << "\n";
}
