// vtkQuadcastPieceRepresentation -- a representation that draws, on each rank, the piece of the data that rank holds
#ifndef vtkQuadcastPieceRepresentation_h
#define vtkQuadcastPieceRepresentation_h

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkNew.h"                         // for vtkNew
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h"                // for vtkSmartPointer

class vtkActor;
class vtkDataObject;
class vtkMapper;

/// The data path of the plugin's isosurface representations: each rank keeps the piece of its
/// input it holds (`Cache`, set by the subclass's RequestData; never moved between ranks or sent to
/// the client) and draws it with the subclass's mapper, and IceT composites the ranks' images by
/// depth. The view is given `DataBounds` (the world box of what the piece draws) for its camera
/// and clipping range. The actor's diffuse colour and transform are set through the properties
/// ParaView's other representations name alike.
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastPieceRepresentation : public vtkPVDataRepresentation {
public:
    vtkAbstractTypeMacro(vtkQuadcastPieceRepresentation, vtkPVDataRepresentation);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    int ProcessViewRequest(vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) override;
    void SetVisibility(bool visible) override;
    void SetDiffuseColor(double r, double g, double b);
    void SetPosition(double x, double y, double z);
    void SetScale(double x, double y, double z);
    void SetOrientation(double x, double y, double z);
    void SetOrigin(double x, double y, double z);

protected:
    vtkQuadcastPieceRepresentation();
    ~vtkQuadcastPieceRepresentation() override;
    bool AddToView(vtkView* view) override;
    bool RemoveFromView(vtkView* view) override;
    /// The subclass's mapper (drawn by `Actor`); called once, from the subclass's constructor.
    void SetMapper(vtkMapper* mapper);

    vtkNew<vtkActor> Actor;
    vtkSmartPointer<vtkDataObject> Cache;            ///< this rank's piece
    double DataBounds[6] = {1, -1, 1, -1, 1, -1};  ///< the world box of what the piece draws

private:
    vtkQuadcastPieceRepresentation(const vtkQuadcastPieceRepresentation&) = delete;
    void operator=(const vtkQuadcastPieceRepresentation&) = delete;
    vtkMapper* Mapper = nullptr;  ///< (the actor holds the reference)
};

#endif
