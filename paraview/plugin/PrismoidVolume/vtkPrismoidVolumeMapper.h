#ifndef vtkPrismoidVolumeMapper_h
#define vtkPrismoidVolumeMapper_h
// Prismoid's interval shading as a VTK volume mapper for unstructured grids of tetrahedra:
// each frame is drawn offscreen with Vulkan (one device per process) from the coloured array,
// the volume property's colour map and opacity function, the camera and the viewport, and its
// premultiplied colour and alpha are drawn over VTK's frame.
#include "PrismoidVolumeModuleModule.h"  // export macro
#include <vtkUnstructuredGridVolumeMapper.h>

#include <string>

class vtkTextureObject;

class PRISMOIDVOLUMEMODULE_EXPORT vtkPrismoidVolumeMapper : public vtkUnstructuredGridVolumeMapper
{
public:
  static vtkPrismoidVolumeMapper* New();
  vtkTypeMacro(vtkPrismoidVolumeMapper, vtkUnstructuredGridVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // 0: the mesh-shader backend (one workgroup per cell), 1: the compute backend (per-tile
  // rasterization, exact per-pixel order).
  vtkSetClampMacro(Backend, int, 0, 1);
  vtkGetMacro(Backend, int);
  // The mesh backend's order: 0 sorted on the GPU by centroid distance, 1 exact (a
  // topological visibility order over face adjacency, made on the CPU each frame).
  vtkSetClampMacro(Ordering, int, 0, 1);
  vtkGetMacro(Ordering, int);
  // 0: emission-absorption colour through the colour map; 1: absorption only (the colour map
  // ignored: the background dimmed by the volume's transmittance).
  vtkSetClampMacro(Quantity, int, 0, 1);
  vtkGetMacro(Quantity, int);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

  // The last frame: whether it was drawn, and the error that stopped it otherwise; the wall
  // time of the plugin's part of it (Prismoid's frame, its read-back and the blend), in ms.
  vtkGetMacro(LastFrameDrawn, bool);
  vtkGetMacro(LastFrameMilliseconds, double);
  // What this process has sent to the GPU: whole meshes, and fields alone (a time step of the
  // mesh drawn before).
  static int GetMeshUploads();
  static int GetFieldUploads();
  const char* GetLastError() const { return this->LastError.c_str(); }

protected:
  vtkPrismoidVolumeMapper();
  ~vtkPrismoidVolumeMapper() override;

  int Backend = 0;
  int Ordering = 0;
  int Quantity = 0;
  bool LastFrameDrawn = false;
  double LastFrameMilliseconds = 0.0;
  std::string LastError;
  std::string ReportedError;  // the error last reported, until a frame is drawn
  std::string ReportedWarning;  // why the last frame showed nothing, said once until it changes
  // Says once (until another reason or a visible frame) why a frame draws nothing.
  void WarnNothingDrawn(const std::string& why);
  vtkTextureObject* Texture = nullptr;
  // Draws a viewport-sized image of premultiplied linear RGBA (rows bottom to top) over the frame.
  void Blend(vtkRenderer* ren, int width, int height, float* premultiplied);

private:
  vtkPrismoidVolumeMapper(const vtkPrismoidVolumeMapper&) = delete;
  void operator=(const vtkPrismoidVolumeMapper&) = delete;
};

#endif
