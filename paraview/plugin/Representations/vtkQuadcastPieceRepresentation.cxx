#include "vtkQuadcastPieceRepresentation.h"

#include "vtkActor.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkMapper.h"
#include "vtkPVRenderView.h"
#include "vtkPVView.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"

vtkQuadcastPieceRepresentation::vtkQuadcastPieceRepresentation() { this->Actor->GetProperty()->SetDiffuseColor(1, 1, 1); }

vtkQuadcastPieceRepresentation::~vtkQuadcastPieceRepresentation() = default;

void vtkQuadcastPieceRepresentation::SetMapper(vtkMapper* mapper) {
    this->Mapper = mapper;
    this->Actor->SetMapper(mapper);
}

void vtkQuadcastPieceRepresentation::SetDiffuseColor(double r, double g, double b) { this->Actor->GetProperty()->SetDiffuseColor(r, g, b); }
void vtkQuadcastPieceRepresentation::SetPosition(double x, double y, double z) { this->Actor->SetPosition(x, y, z); }
void vtkQuadcastPieceRepresentation::SetScale(double x, double y, double z) { this->Actor->SetScale(x, y, z); }
void vtkQuadcastPieceRepresentation::SetOrientation(double x, double y, double z) { this->Actor->SetOrientation(x, y, z); }
void vtkQuadcastPieceRepresentation::SetOrigin(double x, double y, double z) { this->Actor->SetOrigin(x, y, z); }

void vtkQuadcastPieceRepresentation::SetVisibility(bool visible) {
    this->Actor->SetVisibility(visible ? 1 : 0);
    this->Superclass::SetVisibility(visible);
}

int vtkQuadcastPieceRepresentation::ProcessViewRequest(vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo) {
    if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo)) return 0;
    if (request == vtkPVView::REQUEST_UPDATE()) {
        // The piece stays on its rank (never delivered to the client) and is drawn there.
        vtkPVRenderView::SetPiece(inInfo, this, this->Cache, this->Cache ? this->Cache->GetActualMemorySize() : 0, 0);
        vtkPVRenderView::SetDeliverToClientAndRenderingProcesses(inInfo, this, false, false, 0);
        vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
        vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds);
    } else if (request == vtkPVView::REQUEST_RENDER() && this->Mapper) {
        // The piece as delivered here (this rank's own: it is not moved).
        this->Mapper->SetInputConnection(vtkPVRenderView::GetPieceProducer(inInfo, this, 0));
    }
    return 1;
}

bool vtkQuadcastPieceRepresentation::AddToView(vtkView* view) {
    if (auto* rview = vtkPVRenderView::SafeDownCast(view)) {
        rview->GetRenderer()->AddActor(this->Actor);
        return this->Superclass::AddToView(rview);
    }
    return false;
}

bool vtkQuadcastPieceRepresentation::RemoveFromView(vtkView* view) {
    if (auto* rview = vtkPVRenderView::SafeDownCast(view)) {
        rview->GetRenderer()->RemoveActor(this->Actor);
        return this->Superclass::RemoveFromView(rview);
    }
    return false;
}

void vtkQuadcastPieceRepresentation::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    if (this->Mapper) {
        os << indent << "Mapper:\n";
        this->Mapper->PrintSelf(os, indent.GetNextIndent());
    }
}
