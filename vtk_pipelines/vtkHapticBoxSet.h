/**
 * @class   vtkHapticBoxSet
 * @brief   A set of baked haptic boxes (an hb::BoxScene) travelling through a VTK pipeline.
 *
 * Produced by vtkHapticBoxBakeFilter (or wrapping a loaded .hbox file with SetScene) and
 * consumed by vtkHapticBoxErrorFieldFilter. The scene is immutable and shared: ShallowCopy
 * and DeepCopy share the same const hb::BoxScene (its tables are never modified).
 */
#ifndef vtkHapticBoxSet_h
#define vtkHapticBoxSet_h

#include "scene/box_scene.h"
#include <vtkDataObject.h>
#include <memory>

class vtkHapticBoxSet : public vtkDataObject {
public:
  static vtkHapticBoxSet* New();
  vtkTypeMacro(vtkHapticBoxSet, vtkDataObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The boxes (null when empty).
  std::shared_ptr<const hb::BoxScene> GetScene() const { return this->Scene; }
  void SetScene(std::shared_ptr<const hb::BoxScene> scene);

  /// Number of boxes (pieces).
  vtkIdType GetNumberOfBoxes() const;

  void Initialize() override;
  void ShallowCopy(vtkDataObject* src) override;
  void DeepCopy(vtkDataObject* src) override;
  unsigned long GetActualMemorySize() override;

  static vtkHapticBoxSet* GetData(vtkInformation* info);
  static vtkHapticBoxSet* GetData(vtkInformationVector* v, int i = 0);

protected:
  vtkHapticBoxSet();
  ~vtkHapticBoxSet() override;

  std::shared_ptr<const hb::BoxScene> Scene;

private:
  vtkHapticBoxSet(const vtkHapticBoxSet&) = delete;
  void operator=(const vtkHapticBoxSet&) = delete;
};

#endif
