// vtkQuadcastGlyphMapper -- every point of its input drawn as a sphere by quadcast's OpenGL renderer
#ifndef vtkQuadcastGlyphMapper_h
#define vtkQuadcastGlyphMapper_h

#include <memory>

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkPointGaussianMapper.h"

/// Draws each point of its input (a vtkPolyData or a composite data set of them, as
/// vtkPointGaussianRepresentation delivers) as a sphere: quadcast's `sphere` primitive, ray cast
/// per pixel by quadcast::gl::QuadricRenderer in the render window's own OpenGL context and into
/// its bound framebuffer and depth buffer, so that the spheres and the view's other geometry hide
/// each other pixel by pixel (the depth written is the sphere's own, under the view's projection).
///
/// Radius: ScaleFactor, or with a ScaleArray ScaleFactor times the array's ScaleArrayComponent (its
/// magnitude for a component outside the array), through ScaleFunction when one is set. Colour:
/// the mapper's scalar colouring (LookupTable, ColorMode, the selected point array) or the actor's
/// diffuse colour. Light: one white light along the camera's direction of projection (a headlight),
/// with quadcast's shading. The actor's matrix moves the spheres; it must scale uniformly.
/// Not drawn: points with a radius that is not positive and finite, tensors that are not positive
/// definite (both counted in SkippedPoints),
/// hardware selection passes (picking draws nothing).
class vtkPolyData;
class vtkUnsignedCharArray;
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastGlyphMapper : public vtkPointGaussianMapper {
public:
    static vtkQuadcastGlyphMapper* New();
    vtkTypeMacro(vtkQuadcastGlyphMapper, vtkPointGaussianMapper);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    void Render(vtkRenderer* ren, vtkActor* act) override;
    void ReleaseGraphicsResources(vtkWindow* win) override;
    /// The input points' bounds grown by the largest radius (untransformed: the actor applies its matrix).
    double* GetBounds() override;
    void GetBounds(double bounds[6]) override { this->vtkAbstractMapper3D::GetBounds(bounds); }
    bool HasTranslucentPolygonalGeometry() override { return false; }
    bool HasOpaqueGeometry() override { return true; }

    /// What each point is drawn as: SPHERE (radius as above) or TENSOR_ELLIPSOID, the ellipsoid of
    /// the point's symmetric tensor (TensorArray: 9 components, or 6 in VTK's symmetric order
    /// xx yy zz xy yz xz) whose semi-axes are the eigenvectors times their eigenvalues times the
    /// radius (as quadcast::shapes::tensor_ellipsoid and vtkTensorGlyph with eigenvalue scaling).
    /// Tensors that are not positive definite are not drawn (a warning counts them).
    enum GlyphTypes { SPHERE = 0, TENSOR_ELLIPSOID = 1 };
    vtkSetClampMacro(GlyphType, int, SPHERE, TENSOR_ELLIPSOID);
    vtkGetMacro(GlyphType, int);
    vtkSetStringMacro(TensorArray);
    vtkGetStringMacro(TensorArray);

    /// Line cells of the input drawn as capped cylinders of this radius between their consecutive
    /// points (bonds), each half coloured as its end point, moved and scaled with the spheres;
    /// 0 (default): no cylinders.
    vtkSetClampMacro(BondRadius, double, 0.0, 1e30);
    vtkGetMacro(BondRadius, double);

    /// Glyphs uploaded for the last render, and input points left out (radius not positive and finite).
    vtkIdType GetNumberOfGlyphs() const;
    vtkIdType GetSkippedPoints() const;

protected:
    vtkQuadcastGlyphMapper();
    ~vtkQuadcastGlyphMapper() override;

private:
    vtkQuadcastGlyphMapper(const vtkQuadcastGlyphMapper&) = delete;
    void operator=(const vtkQuadcastGlyphMapper&) = delete;
    /// Calls block(polydata) per polygonal block of `input`, then glyph(point id, centre, radius)
    /// per point with a positive finite radius and a finite centre; returns the points left out.
    template <class Block, class Glyph>
    vtkIdType ForEachGlyph(vtkDataObject* input, Block&& block, Glyph&& glyph);
    struct Internals;
    std::unique_ptr<Internals> Internal;
    void AddBonds(vtkPolyData* pd, vtkUnsignedCharArray* mapped, bool& any);
    int GlyphType = SPHERE;
    double BondRadius = 0;
    char* TensorArray = nullptr;
};

#endif
