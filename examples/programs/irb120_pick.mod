MODULE PickPlace
  ! A small IRB 120 pick-and-place module for README.md's "Deploying a calibration": six robtargets
  ! (mm, quaternion w x y z, confdata), a jointtarget (deg) and an inline target. Targets are for the
  ! tool the calibration registered (tGripper), in the robot's base frame.
  PERS tooldata tGripper:=[TRUE,[[40,0,120],[1,0,0,0]],[0.5,[0,0,60],[1,0,0,0],0,0,0]];
  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick1:=[[486.82,185.44,430.57],[0.174033,0.432048,0.808673,0.359297],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick2:=[[429.07,-309.96,340.93],[0.189960,0.205175,0.908020,-0.311958],[-1,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick3:=[[258.25,274.13,355.01],[0.114072,-0.505596,0.837921,0.171023],[0,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick4:=[[655.71,-2.74,387.40],[0.231793,0.746718,0.509966,0.358634],[-1,0,1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick5:=[[514.85,137.64,445.97],[0.396401,-0.370790,0.773304,-0.327690],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick6:=[[373.33,-149.76,389.35],[0.312959,0.047685,0.913076,0.257051],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveAbsJ jHome, v1000, fine, tGripper;
    MoveJ pPick1, v1000, z50, tGripper;
    MoveL pPick2, v200, fine, tGripper;
    MoveL pPick3, v200, z10, tGripper;
    MoveJ pPick4, v1000, z50, tGripper;
    MoveL [[399.37,78.31,217.48],[0.027458,0.182509,0.979807,0.076911],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], v100, fine, tGripper;
    MoveL pPick5, v200, fine, tGripper;
    MoveJ pPick6, v1000, z50, tGripper;
    MoveAbsJ jHome, v1000, fine, tGripper;
  ENDPROC
ENDMODULE
