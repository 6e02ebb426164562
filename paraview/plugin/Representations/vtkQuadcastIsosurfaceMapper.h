// vtkQuadcastIsosurfaceMapper -- the isosurface of image data's spline (QSS, S31) or trilinear reconstruction, ray cast by quadcast
#ifndef vtkQuadcastIsosurfaceMapper_h
#define vtkQuadcastIsosurfaceMapper_h

#include <memory>

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkMapper.h"

/// Draws the isosurface Isovalue of a vtkImageData's point array (ScalarArray, one component)
/// as quadcast's OpenGL isosurface renderer ray casts it (quadcast::gl::IsosurfaceRenderer): the
/// quadratic (QSS) or cubic (S31) spline on the type-6 tetrahedral partition, or the trilinear
/// interpolant, intersected exactly per pixel in the render window's own context and depth
/// buffer, so the surface and the view's other geometry hide each other pixel by pixel.
///
/// A piece of an image split over MPI ranks draws only its own cubes: OwnedExtent is the part of
/// the input's extent that is not ghost (the samples a rank owns, sharing the boundary sample
/// with the next piece as VTK's pieces do) and WholeExtent the whole image's. Spline cubes are
/// centred on samples: a piece draws those of its owned samples except the last along an axis
/// (the next piece's first), unless that is the whole image's last; trilinear cells lie between
/// samples, and a piece draws those of its owned extent. The ghost samples around (one layer)
/// complete the stencils of the boundary cubes, so the pieces join without a seam.
///
/// Colour: the actor's diffuse colour; one white headlight; quadcast's Blinn-Phong shading. The
/// actor may translate and scale (each axis by a positive factor), not rotate; an image with a
/// direction matrix other than the identity, or with samples that are not finite, is an error
/// (nothing drawn). Hardware selection passes draw nothing.
class vtkImageData;
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastIsosurfaceMapper : public vtkMapper {
public:
    static vtkQuadcastIsosurfaceMapper* New();
    vtkTypeMacro(vtkQuadcastIsosurfaceMapper, vtkMapper);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    enum Schemes { QSS = 0, S31 = 1, TRILINEAR = 2 };
    vtkSetClampMacro(Scheme, int, QSS, TRILINEAR);
    vtkGetMacro(Scheme, int);
    vtkSetMacro(Isovalue, double);
    vtkGetMacro(Isovalue, double);
    /// The point array whose isosurface is drawn (null: the active scalars).
    vtkSetStringMacro(ScalarArray);
    vtkGetStringMacro(ScalarArray);
    /// The input's own (non-ghost) point extent and the whole image's; both default to the
    /// input's extent (an empty extent, max < min, means that).
    vtkSetVector6Macro(OwnedExtent, int);
    vtkGetVector6Macro(OwnedExtent, int);
    vtkSetVector6Macro(WholeExtent, int);
    vtkGetVector6Macro(WholeExtent, int);

    void Render(vtkRenderer* ren, vtkActor* act) override;
    void ReleaseGraphicsResources(vtkWindow* win) override;
    /// The world box of the cubes (cells) drawn, untransformed (the actor applies its matrix).
    double* GetBounds() override;
    void GetBounds(double bounds[6]) override { this->vtkAbstractMapper3D::GetBounds(bounds); }
    bool HasTranslucentPolygonalGeometry() override { return false; }
    bool HasOpaqueGeometry() override { return true; }

    /// The world box of the cubes (cells) `scheme` draws of `image` with these extents (as GetBounds).
    static void DrawnBounds(vtkImageData* image, int scheme, const int owned[6], const int whole[6], double bounds[6]);

    /// Of the last render: cubes (cells) whose range contains the isovalue, and tetrahedra (cells) drawn.
    vtkIdType GetNumberOfActiveCubes() const;
    vtkIdType GetNumberOfDrawnElements() const;

protected:
    vtkQuadcastIsosurfaceMapper();
    ~vtkQuadcastIsosurfaceMapper() override;
    int FillInputPortInformation(int port, vtkInformation* info) override;

private:
    vtkQuadcastIsosurfaceMapper(const vtkQuadcastIsosurfaceMapper&) = delete;
    void operator=(const vtkQuadcastIsosurfaceMapper&) = delete;
    /// (Re)prepares the volume when the input or a property changed; false (error reported) when it cannot be drawn.
    bool Prepare();
    struct Internals;
    std::unique_ptr<Internals> Internal;
    int Scheme = QSS;
    double Isovalue = 0;
    char* ScalarArray = nullptr;
    int OwnedExtent[6] = {0, -1, 0, -1, 0, -1};
    int WholeExtent[6] = {0, -1, 0, -1, 0, -1};
};

#endif
