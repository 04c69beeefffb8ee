//! A plain rapier world of the user's (what any rapier application already has): the sets,
//! the pipeline and its parameters. Nothing here is flapwing's.

use rapier3d_f64::prelude::*;

/// Everything a rapier application steps.
pub struct World {
    pub bodies: RigidBodySet,
    pub colliders: ColliderSet,
    pub params: IntegrationParameters,
    pub gravity: Vector,
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad: BroadPhaseBvh,
    narrow: NarrowPhase,
    joints: ImpulseJointSet,
    multibody: MultibodyJointSet,
    soft: SoftBodySet,
    ccd: CCDSolver,
}

impl World {
    /// An empty world stepping by `dt_s` under gravity `g_m_s2` (metres: length_unit 1).
    pub fn new(dt_s: f64, g_m_s2: f64, solver_iterations: usize) -> Self {
        let params = IntegrationParameters {
            dt: dt_s,
            length_unit: 1.0,
            num_solver_iterations: solver_iterations,
            ..IntegrationParameters::default()
        };
        Self {
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            params,
            gravity: Vector::new(0.0, 0.0, -g_m_s2),
            pipeline: PhysicsPipeline::new(),
            islands: IslandManager::new(),
            broad: BroadPhaseBvh::new(),
            narrow: NarrowPhase::new(),
            joints: ImpulseJointSet::new(),
            multibody: MultibodyJointSet::new(),
            soft: SoftBodySet::new(),
            ccd: CCDSolver::new(),
        }
    }

    /// One step of the pipeline.
    pub fn step(&mut self) {
        self.pipeline.step(
            self.gravity,
            &self.params,
            &mut self.islands,
            &mut self.broad,
            &mut self.narrow,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.joints,
            &mut self.multibody,
            &mut self.soft,
            &mut self.ccd,
            &(),
            &(),
        );
    }
}
