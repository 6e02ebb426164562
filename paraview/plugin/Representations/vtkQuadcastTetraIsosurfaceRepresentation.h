// vtkQuadcastTetraIsosurfaceRepresentation -- ParaView's "Tetra Isosurface": the exact isosurface of linear and quadratic tetrahedra
#ifndef vtkQuadcastTetraIsosurfaceRepresentation_h
#define vtkQuadcastTetraIsosurfaceRepresentation_h

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkNew.h"                         // for vtkNew
#include "vtkQuadcastPieceRepresentation.h"

class vtkQuadcastTetraIsosurfaceMapper;

/// The isosurface of a point array of an unstructured grid on its linear and quadratic
/// tetrahedra, one quadric per element (vtkQuadcastTetraIsosurfaceMapper); each rank draws the
/// cells it holds (vtkQuadcastPieceRepresentation). No ghost cells are needed: each element's
/// piece depends on its own nodes only.
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastTetraIsosurfaceRepresentation : public vtkQuadcastPieceRepresentation {
public:
    static vtkQuadcastTetraIsosurfaceRepresentation* New();
    vtkTypeMacro(vtkQuadcastTetraIsosurfaceRepresentation, vtkQuadcastPieceRepresentation);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    /// vtkQuadcastTetraIsosurfaceMapper's Isovalue and scalar array (the first four arguments
    /// are those of ParaView's array selection, unused).
    void SetIsovalue(double value);
    void SelectScalarArray(int, int, int, int, const char* name);

protected:
    vtkQuadcastTetraIsosurfaceRepresentation();
    ~vtkQuadcastTetraIsosurfaceRepresentation() override;
    int FillInputPortInformation(int port, vtkInformation* info) override;
    int RequestData(vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector) override;

private:
    vtkQuadcastTetraIsosurfaceRepresentation(const vtkQuadcastTetraIsosurfaceRepresentation&) = delete;
    void operator=(const vtkQuadcastTetraIsosurfaceRepresentation&) = delete;
    vtkNew<vtkQuadcastTetraIsosurfaceMapper> Mapper;
};

#endif
