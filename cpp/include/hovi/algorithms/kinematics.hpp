// Forward kinematics on the tree (paper Sec. 2.3): g_i = g_par g_{par,i}(0) exp(S^_i q_i),
// S̄_i = Ad_{g_i} S_i, M̄_i = Ad^{-T} M_i Ad^{-1}, v̄_i = v̄_par + S̄_i q̇_i.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {

// Throws InputError unless x has n entries, all finite.
void check_vector(const char* name, const Eigen::Ref<const VecX>& x, int n);

// Fills data.g, data.Sbar, data.Mbar.
void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q);
// Also fills data.v.
void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                        const Eigen::Ref<const VecX>& qdot);

// Pose of joint frame i in the world (Pinocchio's oMi) after forward_kinematics.
SE3 joint_placement(const Model& model, const Data& data, int i);

// The spatial gravity wrench on body i at the world origin, F̄_i = [m p̂_i g; m g] (docs/paper.md C-4).
Wrench gravity_wrench(const Model& model, const Data& data, int i);

}  // namespace hovi
