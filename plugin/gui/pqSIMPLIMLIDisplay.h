// How an MLI is shown in a ParaView render view (issue 11 item 5): as `simpli render` shows it,
// without the user setting anything. An MLI is recognised by its data, not by the proxy that
// made it: the reference camera in the output's field data (CameraIntrinsics, CameraExtrinsics,
// CameraImageSize; filters/SIMPLIMLIToVTK.h), so the reader, Build MLI and any filter that
// passes the collection through are all shown the same way.
//
// Only the builtin session (the GUI's default) is handled: the camera is read from the output
// in this process. With a remote server the functions return false and nothing changes.
#pragma once

#include <QString>

class pqDataRepresentation;
class pqOutputPort;
class pqRenderView;

namespace simpli::pv {

/// Number of layers of the MLI at `port`, 0 when the port's data is not an MLI (or is remote).
int mliLayerCount(pqOutputPort* port);

/// Shows the representation as the MLI's pixels: colours = the RGBA point scalars used directly
/// (MapScalars off; ParaView's default maps them through a colour map), unlit, surface; and
/// makes its view blend the layers back to front (depth peeling with one peel per layer and a
/// spare: the layers of one collection are drawn by one mapper, so their order must come from
/// peeling). False when the representation does not show an MLI.
bool showAsCaptured(pqDataRepresentation* representation);

/// Puts `view`'s camera at the MLI's reference camera (position, orientation, vertical view
/// angle, principal point as window centre) and renders. False, with the reason in `why`, when
/// the port is not an MLI or its camera cannot be a vtkCamera (non-square pixels).
bool applyReferenceCamera(pqRenderView* view, pqOutputPort* port, QString* why = nullptr);

} // namespace simpli::pv
