#include "mcpose/analysis/visible_instances.h"

#include <map>

#include "mcpose/eval.h"

namespace mcpose::analysis {

Status ForEachVisibleInstance(const Dataset& dataset, bool real_only,
                              const std::function<Status(const VisibleInstance&)>& visit,
                              void (*progress)(int done, int total)) {
  std::map<int, Mesh> meshes;
  std::map<int, std::vector<Eigen::Vector3f>> points;
  const std::vector<FrameKey> frames = dataset.Frames();
  int done = 0;
  for (const FrameKey& key : frames) {
    if (!real_only || key.scene_id != kSyntheticScene) {
      MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset.LoadFrame(key));
      for (const GtInstance& gt : frame.gt) {
        MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset.LoadVisibleMask(key, gt));
        Detection tight;
        if (MaskBox(mask, &tight) == 0) continue;
        if (!meshes.count(gt.obj_id)) {
          MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset.LoadMesh(gt.obj_id));
          MCPOSE_ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> pts, dataset.LoadEvalPoints(gt.obj_id));
          meshes[gt.obj_id] = std::move(mesh);
          points[gt.obj_id] = std::move(pts);
        }
        MCPOSE_RETURN_IF_ERROR(visit(VisibleInstance{frame, gt, tight, meshes[gt.obj_id], points[gt.obj_id]}));
      }
    }
    if (progress) progress(++done, static_cast<int>(frames.size()));
  }
  return Status::Ok();
}

}  // namespace mcpose::analysis
