// vtkQuadcastGlyphRepresentation -- ParaView's "Quadric Glyphs": points as spheres ray cast by quadcast
#ifndef vtkQuadcastGlyphRepresentation_h
#define vtkQuadcastGlyphRepresentation_h

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkPointGaussianRepresentation.h"

class vtkQuadcastGlyphMapper;

/// The data path of ParaView's Point Gaussian representation (every point of any data set,
/// delivered to the rendering ranks, ordered compositing, scalar colouring through the lookup
/// table, radius from GlyphRadius / SetSplatSize and a scale array) with quadcast's mapper, which
/// draws each point as an exact sphere. The scale array's values are used as they are (no scale
/// transfer function by default).
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastGlyphRepresentation : public vtkPointGaussianRepresentation {
public:
    static vtkQuadcastGlyphRepresentation* New();
    vtkTypeMacro(vtkQuadcastGlyphRepresentation, vtkPointGaussianRepresentation);
    void PrintSelf(ostream& os, vtkIndent indent) override;
    /// The mapper (for tests and host code: glyph counts).
    vtkQuadcastGlyphMapper* GetGlyphMapper();
    /// Spheres (0) or tensor ellipsoids (1) of the point array selected by SelectTensorArray
    /// (vtkQuadcastGlyphMapper::SetGlyphType, SetTensorArray).
    void SetGlyphType(int type);
    /// The tensor array (the first four arguments are those of ParaView's array selection, unused).
    void SelectTensorArray(int, int, int, int, const char* name);
    /// Line cells drawn as capped cylinders of this radius (vtkQuadcastGlyphMapper::SetBondRadius); 0: none.
    void SetBondRadius(double r);

protected:
    /// The Point Gaussian representation's points, plus the line cells of a polygonal input (the
    /// bonds): vtkMaskPoints there keeps every point in order, so the cells' point ids hold.
    int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
    vtkQuadcastGlyphRepresentation();
    ~vtkQuadcastGlyphRepresentation() override;

private:
    vtkQuadcastGlyphRepresentation(const vtkQuadcastGlyphRepresentation&) = delete;
    void operator=(const vtkQuadcastGlyphRepresentation&) = delete;
};

#endif
