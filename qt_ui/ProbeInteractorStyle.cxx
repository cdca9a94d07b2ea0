#include "ProbeInteractorStyle.h"
#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

vtkStandardNewMacro(ProbeInteractorStyle);

void ProbeInteractorStyle::OnLeftButtonDown() {
  vtkRenderWindowInteractor* rwi = this->Interactor;
  if (this->ProbeMode && this->ProbeCallback && !rwi->GetShiftKey() && !rwi->GetControlKey()) {
    const int* p = rwi->GetEventPosition();
    if (this->ProbeCallback(p[0], p[1], true)) {
      this->Dragging = true;
      return;
    }
  }
  this->Superclass::OnLeftButtonDown();
}

void ProbeInteractorStyle::OnLeftButtonUp() {
  if (this->Dragging) {
    this->Dragging = false;
    return;
  }
  this->Superclass::OnLeftButtonUp();
}

void ProbeInteractorStyle::OnMouseMove() {
  if (this->Dragging) {
    const int* p = this->Interactor->GetEventPosition();
    this->ProbeCallback(p[0], p[1], false);
    return;
  }
  this->Superclass::OnMouseMove();
}

void ProbeInteractorStyle::OnMouseWheelForward() {
  if (this->Interactor->GetControlKey() && this->DepthCallback) {
    this->DepthCallback(+1);
    return;
  }
  this->Superclass::OnMouseWheelForward();
}

void ProbeInteractorStyle::OnMouseWheelBackward() {
  if (this->Interactor->GetControlKey() && this->DepthCallback) {
    this->DepthCallback(-1);
    return;
  }
  this->Superclass::OnMouseWheelBackward();
}
