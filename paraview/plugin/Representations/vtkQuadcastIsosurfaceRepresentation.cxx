#include "vtkQuadcastIsosurfaceRepresentation.h"

#include <algorithm>

#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkQuadcastIsosurfaceMapper.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

vtkStandardNewMacro(vtkQuadcastIsosurfaceRepresentation);

vtkQuadcastIsosurfaceRepresentation::vtkQuadcastIsosurfaceRepresentation() { this->SetMapper(this->Mapper); }

vtkQuadcastIsosurfaceRepresentation::~vtkQuadcastIsosurfaceRepresentation() = default;

vtkQuadcastIsosurfaceMapper* vtkQuadcastIsosurfaceRepresentation::GetIsosurfaceMapper() { return this->Mapper; }

void vtkQuadcastIsosurfaceRepresentation::SetIsovalue(double value) { this->Mapper->SetIsovalue(value); }
void vtkQuadcastIsosurfaceRepresentation::SetScheme(int scheme) {
    if (scheme == this->Mapper->GetScheme()) return;
    this->Mapper->SetScheme(scheme);
    this->MarkModified();  // (the bounds given to the view depend on it)
}

void vtkQuadcastIsosurfaceRepresentation::SetGhostLevels(int levels) {
    levels = std::clamp(levels, 0, 1);
    if (levels == this->GhostLevels) return;
    this->GhostLevels = levels;
    this->MarkModified();  // (the input is asked again)
}
void vtkQuadcastIsosurfaceRepresentation::SelectScalarArray(int, int, int, int, const char* name) {
    this->Mapper->SetScalarArray(name && name[0] ? name : nullptr);
}

int vtkQuadcastIsosurfaceRepresentation::FillInputPortInformation(int, vtkInformation* info) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
}

int vtkQuadcastIsosurfaceRepresentation::RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
                                                             vtkInformationVector* outputVector) {
    this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);  // (this rank's piece, no ghosts)
    for (int k = 0; k < inputVector[0]->GetNumberOfInformationObjects(); ++k) {
        vtkInformation* info = inputVector[0]->GetInformationObject(k);
        if (info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
            info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), this->GhostLevels);
    }
    return 1;
}

namespace {

/// The point extent of the image's cells that are not ghosts (the cell ghost array VTK's
/// pipeline writes for a piece with ghost levels); the whole extent when there is none.
void own_extent(vtkImageData* image, int own[6]) {
    image->GetExtent(own);
    auto* ghosts = vtkUnsignedCharArray::SafeDownCast(image->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
    if (!ghosts || image->GetNumberOfCells() == 0) return;
    int ext[6], cells[6] = {0, -1, 0, -1, 0, -1};
    image->GetExtent(ext);
    const int cx = std::max(1, ext[1] - ext[0]), cy = std::max(1, ext[3] - ext[2]);
    bool any = false;
    for (vtkIdType c = 0, n = ghosts->GetNumberOfTuples(); c < n; ++c) {
        if (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL) continue;
        const int ijk[3] = {static_cast<int>(c % cx), static_cast<int>((c / cx) % cy), static_cast<int>(c / (static_cast<vtkIdType>(cx) * cy))};
        for (int a = 0; a < 3; ++a) {
            cells[2 * a] = any ? std::min(cells[2 * a], ijk[a]) : ijk[a];
            cells[2 * a + 1] = any ? std::max(cells[2 * a + 1], ijk[a]) : ijk[a];
        }
        any = true;
    }
    if (!any) return;
    for (int a = 0; a < 3; ++a) {
        if (ext[2 * a] == ext[2 * a + 1]) continue;  // (a flat axis: its one sample)
        own[2 * a] = ext[2 * a] + cells[2 * a];
        own[2 * a + 1] = ext[2 * a] + cells[2 * a + 1] + 1;
    }
}

}  // namespace

int vtkQuadcastIsosurfaceRepresentation::RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                                                     vtkInformationVector* outputVector) {
    vtkMath::UninitializeBounds(this->DataBounds);
    auto cache = vtkSmartPointer<vtkImageData>::New();
    this->Cache = cache;
    if (inputVector[0]->GetNumberOfInformationObjects() == 1) {
        if (vtkImageData* input = vtkImageData::GetData(inputVector[0], 0)) {
            cache->ShallowCopy(input);
            int own[6], whole[6];
            own_extent(input, own);
            vtkStreamingDemandDrivenPipeline::GetWholeExtent(inputVector[0]->GetInformationObject(0), whole);
            if (this->Mapper->GetScheme() == vtkQuadcastIsosurfaceMapper::TRILINEAR &&
                (whole[0] == whole[1] || whole[2] == whole[3] || whole[4] == whole[5]))
                vtkErrorMacro(<< "Spline Isosurface: the image has one sample along an axis: it has no trilinear cells (QSS and S31 draw it); nothing drawn");
            this->Mapper->SetOwnedExtent(own);
            this->Mapper->SetWholeExtent(whole);
            vtkQuadcastIsosurfaceMapper::DrawnBounds(cache, this->Mapper->GetScheme(), own, whole, this->DataBounds);
        }
    }
    return this->Superclass::RequestData(request, inputVector, outputVector);
}

void vtkQuadcastIsosurfaceRepresentation::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "GhostLevels: " << this->GhostLevels << "\n";
}
