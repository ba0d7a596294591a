#pragma once
// What a Bullet collision object is, stored in its user index. Vehicles use kVehicleBase + slot.
namespace roar::sim {
enum SurfaceId : int { kRoad = 1, kGround = 2, kBarrier = 3, kVehicleBase = 1000 };
}
