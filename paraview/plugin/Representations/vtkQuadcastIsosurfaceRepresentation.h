// vtkQuadcastIsosurfaceRepresentation -- ParaView's "Spline Isosurface": image data's isosurface ray cast by quadcast
#ifndef vtkQuadcastIsosurfaceRepresentation_h
#define vtkQuadcastIsosurfaceRepresentation_h

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkNew.h"                         // for vtkNew
#include "vtkQuadcastPieceRepresentation.h"

class vtkQuadcastIsosurfaceMapper;

/// The isosurface of a point array of image data, ray cast exactly on its QSS or S31 spline or
/// trilinear interpolant by vtkQuadcastIsosurfaceMapper; each rank draws the piece of the image it
/// holds (vtkQuadcastPieceRepresentation). With more than one rank the representation asks its
/// input for one ghost level, so that every piece holds the samples around its own and the
/// splines' stencils match across the split: the pieces' surfaces join without a seam (the ghost
/// samples' own cubes are drawn by the piece that owns them).
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastIsosurfaceRepresentation : public vtkQuadcastPieceRepresentation {
public:
    static vtkQuadcastIsosurfaceRepresentation* New();
    vtkTypeMacro(vtkQuadcastIsosurfaceRepresentation, vtkQuadcastPieceRepresentation);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    /// vtkQuadcastIsosurfaceMapper's Isovalue, Scheme (0 QSS, 1 S31, 2 trilinear) and scalar
    /// array (the first four arguments are those of ParaView's array selection, unused).
    void SetIsovalue(double value);
    void SetScheme(int scheme);
    void SelectScalarArray(int, int, int, int, const char* name);
    /// Ghost levels asked of the input when it is split over several ranks (default 1; 0 is a
    /// test switch that shows the seam a split leaves without them).
    void SetGhostLevels(int levels);
    vtkGetMacro(GhostLevels, int);

    vtkQuadcastIsosurfaceMapper* GetIsosurfaceMapper();

protected:
    vtkQuadcastIsosurfaceRepresentation();
    ~vtkQuadcastIsosurfaceRepresentation() override;
    int FillInputPortInformation(int port, vtkInformation* info) override;
    int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector) override;
    int RequestData(vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector) override;

private:
    vtkQuadcastIsosurfaceRepresentation(const vtkQuadcastIsosurfaceRepresentation&) = delete;
    void operator=(const vtkQuadcastIsosurfaceRepresentation&) = delete;
    vtkNew<vtkQuadcastIsosurfaceMapper> Mapper;
    int GhostLevels = 1;
};

#endif
