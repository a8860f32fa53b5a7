(JOB TEST-1 PART PT-4002)
(ORDER QTY=20 MATERIAL C45)
(SUBMITTED 1970-01-01 00:00:00 UTC BY test)
(MACHINE M02 LinuxCNC 2.9)
(PLANAR SPIRAL GROOVE R 60 PITCH 16 TURNS 3 WIDTH 10 DEPTH 4 MM)
(TOOL EM-10 end-mill D10 CORNER R0 Z4)
(SPIRAL R1 60.0000 R2 12.0000 TURNS 3 STEP 16.0000 SENSE CW CLIMB)
(COVERAGE OK MAX GAP 0.0040 MM MAX DEVIATION 0.0050 MM TOLERANCE 0.005 MM)
(ORIGIN FACE CENTRE G54 Z0 ON THE FACE)
(CASES MC-GROOVE-C45-60 CONFIDENCE 0.46)
(gearcam-model 0.1.0 gearcam-template 0.1.0)
(variable table: every shape, process and tool value is a named parameter)
#<r1> = 60  (tool-centre start radius R1, mm)
#<r2> = 12  (tool-centre end radius R2, mm)
#<theta0> = 0  (start angle, degrees)
#<total> = 1080  (sweep, degrees = 360 x turns)
#<chords> = 731  (chords along the spiral, from the tolerance)
#<sense> = -1  (+1 counter-clockwise, -1 clockwise)
#<depth> = 4  (total depth below the face, mm)
#<passes> = 4  (depth passes)
#<feed> = 611.2  (feed along the spiral, mm/min)
#<plunge> = 152.8  (plunge feed, mm/min)
#<rpm> = 3820  (spindle speed, rpm)
#<safe> = 5  (safe height above the face, mm)
G21 G90 G17 G94 G40 G49 G80
S[#<rpm>] M3
G0 Z[#<safe>]
#<pass> = 1
o100 while [#<pass> LE #<passes>]
  #<z> = [0 - #<depth> * #<pass> / #<passes>]
  G0 @[#<r1>] ^[#<theta0>]
  G1 Z[#<z>] F[#<plunge>]
  F[#<feed>]
  #<k> = 0
  o110 while [#<k> LT #<chords>]
    #<k> = [#<k> + 1]
    #<phi> = [#<total> * #<k> / #<chords>]
    G1 @[#<r1> + [#<r2> - #<r1>] * #<phi> / #<total>] ^[#<theta0> + #<sense> * #<phi>]
  o110 endwhile
  G0 Z[#<safe>]
  #<pass> = [#<pass> + 1]
o100 endwhile
M5
M2
