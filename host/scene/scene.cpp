#include "scene/scene.h"

namespace whitted {

size_t csgLeafCount(const Csg& csg) {
    size_t count = 0;
    for (const CsgChild& child : csg.children) {
        const Csg* nested = std::get_if<Csg>(&child.shape);
        count += nested ? csgLeafCount(*nested) : 1;
    }
    return count;
}

}  // namespace whitted
